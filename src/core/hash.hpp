// FNV-1a 64-bit hash (private header): checkpoint checksums and the scene
// fingerprint. Not cryptographic; it detects truncation and bit rot, and
// tells two scenes apart. (Fowler, Noll, Vo: http://www.isthe.com/chongo/tech/comp/fnv/)
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace pbf::detail {

inline constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ull;

inline std::uint64_t fnv1a64(const void* data, std::size_t size,
                             std::uint64_t hash = kFnvOffsetBasis) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
        hash ^= bytes[i];
        hash *= 1099511628211ull;
    }
    return hash;
}

inline std::uint64_t fnv1a64(std::string_view text) {
    return fnv1a64(text.data(), text.size());
}

}  // namespace pbf::detail
