// Little-endian binary payloads of checkpoints (private header): a writer
// that appends values, arrays and strings, and a bounds-checked reader whose
// errors name the file and what was being read.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "pbf/io/io.hpp"

namespace pbf::detail {

[[noreturn]] inline void fail(const std::string& name, const std::string& message) {
    throw IoError(name + ": " + message);
}

inline constexpr std::uint64_t kMaxStringBytes = std::uint64_t{1} << 40;

class BinaryWriter {
  public:
    template <class T>
    void value(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
    template <class T>
    void array(const std::vector<T>& values) {
        value<std::uint64_t>(values.size());
        if (values.empty()) return;  // data() may be null
        bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    }
    void string(const std::string& s) {
        value<std::uint64_t>(s.size());
        bytes_.append(s);
    }
    const std::string& bytes() const { return bytes_; }

  private:
    std::string bytes_;
};

// Bounds-checked reads from the payload: a corrupt length can never make it
// read past the end or allocate more than the file holds.
class BinaryReader {
  public:
    BinaryReader(const std::string& bytes, const std::string& name) : bytes_(bytes), name_(name) {}

    template <class T>
    T value(const char* what) {
        T v;
        need(sizeof(T), what);
        std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return v;
    }
    template <class T>
    void array(std::vector<T>& out, const char* what) {
        const auto n = value<std::uint64_t>(what);
        if (n > (bytes_.size() - pos_) / sizeof(T))
            fail(name_, std::string("corrupt checkpoint: ") + what + " length");
        out.resize(static_cast<std::size_t>(n));
        if (out.empty()) return;  // memcpy must not see the null data() of an empty vector
        std::memcpy(out.data(), bytes_.data() + pos_, out.size() * sizeof(T));
        pos_ += out.size() * sizeof(T);
    }
    std::string string(const char* what) {
        const auto n = value<std::uint64_t>(what);
        if (n > kMaxStringBytes)
            fail(name_, std::string("corrupt checkpoint: ") + what + " length");
        need(static_cast<std::size_t>(n), what);
        std::string s = bytes_.substr(pos_, static_cast<std::size_t>(n));
        pos_ += s.size();
        return s;
    }
    bool atEnd() const { return pos_ == bytes_.size(); }
    // Throws IoError "<file>: message".
    [[noreturn]] void reject(const std::string& message) const { fail(name_, message); }

  private:
    void need(std::size_t n, const char* what) const {
        if (n > bytes_.size() - pos_)
            fail(name_, std::string("corrupt checkpoint: truncated at ") + what);
    }
    const std::string& bytes_;
    const std::string& name_;
    std::size_t pos_ = 0;
};

}  // namespace pbf::detail
