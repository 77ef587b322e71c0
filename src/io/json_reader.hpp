// Strict reading of a JSON object (private header): every getter names the
// field in its error, and finish() rejects keys nobody asked for.
#pragma once

#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "pbf/core/vec3.hpp"
#include "pbf/io/scene.hpp"

namespace pbf::detail {

class JsonReader {
  public:
    // `path` is the field path of `object` ("" for the document, "solver", ...).
    JsonReader(const nlohmann::json& object, std::string path, const std::string& file);

    bool has(const std::string& key) const;
    float number(const std::string& key, float fallback);
    int integer(const std::string& key, int fallback);
    bool boolean(const std::string& key, bool fallback);
    std::string string(const std::string& key, const std::string& fallback);
    Vec3 vec3(const std::string& key, const Vec3& fallback);
    Vec3 requiredVec3(const std::string& key);
    JsonReader object(const std::string& key);            // an empty object if absent
    const nlohmann::json& array(const std::string& key);  // an empty array if absent
    // Throws for the first key that no getter read.
    void finish() const;

    std::string field(const std::string& key) const {
        return path_.empty() ? key : path_ + "." + key;
    }
    [[noreturn]] void fail(const std::string& key, const std::string& message) const;
    const std::string& file() const { return file_; }  // the scene file, for nested readers

  private:
    const nlohmann::json* value(const std::string& key);

    const nlohmann::json& object_;
    std::string path_;
    const std::string& file_;
    std::set<std::string> read_;
};

}  // namespace pbf::detail
