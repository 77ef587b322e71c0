#include "io/json_reader.hpp"

#include <cmath>
#include <limits>

namespace pbf::detail {
namespace {

const nlohmann::json& emptyObject() {
    static const nlohmann::json empty = nlohmann::json::object();
    return empty;
}
const nlohmann::json& emptyArray() {
    static const nlohmann::json empty = nlohmann::json::array();
    return empty;
}

std::string typeName(const nlohmann::json& v) {
    return v.type_name();
}

// A value as quoted in an error message. Overrides can put strings that are
// not UTF-8 into the document and dump() throws on those by default (found by
// fuzz/fuzz_override): replace bad bytes, and keep long values short.
std::string show(const nlohmann::json& v) {
    std::string text = v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (text.size() > 200) text = text.substr(0, 200) + "...";
    return text;
}

}  // namespace

JsonReader::JsonReader(const nlohmann::json& object, std::string path, const std::string& file)
    : object_(object), path_(std::move(path)), file_(file) {
    if (!object_.is_object())
        throw SceneError(file_ + ": " + (path_.empty() ? std::string("document") : path_) +
                         ": expected an object, got " + typeName(object_));
}

void JsonReader::fail(const std::string& key, const std::string& message) const {
    throw SceneError(file_ + ": " + field(key) + ": " + message);
}

bool JsonReader::has(const std::string& key) const {
    return object_.contains(key);
}

const nlohmann::json* JsonReader::value(const std::string& key) {
    read_.insert(key);
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
}

float JsonReader::number(const std::string& key, float fallback) {
    const nlohmann::json* v = value(key);
    if (!v) return fallback;
    if (!v->is_number()) fail(key, "expected a number, got " + typeName(*v));
    const double d = v->get<double>();
    if (!std::isfinite(d) || std::fabs(d) > double(std::numeric_limits<float>::max()))
        fail(key, "number out of range");
    return static_cast<float>(d);
}

int JsonReader::integer(const std::string& key, int fallback) {
    const nlohmann::json* v = value(key);
    if (!v) return fallback;
    if (!v->is_number_integer()) fail(key, "expected an integer, got " + show(*v));
    const auto i = v->get<long long>();
    if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max())
        fail(key, "integer out of range, got " + show(*v));
    return static_cast<int>(i);
}

bool JsonReader::boolean(const std::string& key, bool fallback) {
    const nlohmann::json* v = value(key);
    if (!v) return fallback;
    if (!v->is_boolean()) fail(key, "expected true or false, got " + show(*v));
    return v->get<bool>();
}

std::string JsonReader::string(const std::string& key, const std::string& fallback) {
    const nlohmann::json* v = value(key);
    if (!v) return fallback;
    if (!v->is_string()) fail(key, "expected a string, got " + typeName(*v));
    return v->get<std::string>();
}

Vec3 JsonReader::vec3(const std::string& key, const Vec3& fallback) {
    const nlohmann::json* v = value(key);
    if (!v) return fallback;
    if (!v->is_array() || v->size() != 3)
        fail(key, "expected an array of 3 numbers [x, y, z], got " + show(*v));
    float c[3];
    for (std::size_t k = 0; k < 3; ++k) {
        const nlohmann::json& e = (*v)[k];
        if (!e.is_number() || !std::isfinite(e.get<double>()) || std::fabs(e.get<double>()) > 1e30)
            fail(key, "expected an array of 3 finite numbers, got " + show(*v));
        c[k] = static_cast<float>(e.get<double>());
    }
    return {c[0], c[1], c[2]};
}

Vec3 JsonReader::requiredVec3(const std::string& key) {
    if (!has(key)) fail(key, "missing (required)");
    return vec3(key, {});
}

JsonReader JsonReader::object(const std::string& key) {
    const nlohmann::json* v = value(key);
    return JsonReader(v ? *v : emptyObject(), field(key), file_);
}

const nlohmann::json& JsonReader::array(const std::string& key) {
    const nlohmann::json* v = value(key);
    if (!v) return emptyArray();
    if (!v->is_array()) fail(key, "expected an array, got " + typeName(*v));
    return *v;
}

void JsonReader::finish() const {
    for (const auto& [key, v] : object_.items()) {
        if (read_.count(key)) continue;
        std::string known;
        for (const std::string& k : read_) known += (known.empty() ? "" : ", ") + k;
        fail(key, "unknown key (known keys here: " + known + ")");
    }
}

}  // namespace pbf::detail
