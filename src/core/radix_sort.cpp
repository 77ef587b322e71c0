#include "core/radix_sort.hpp"

#include <algorithm>

#include "core/parallel.hpp"
#include "pbf/core/threading.hpp"

namespace pbf::detail {
namespace {

constexpr int kDigitBits = 11;
constexpr std::uint64_t kDigits = std::uint64_t{1} << kDigitBits;

}  // namespace

void RadixSort::sort(std::uint64_t* keys, std::size_t n, int bits, std::uint32_t* perm,
                     std::span<std::byte> scratch) {
    // The passes that move something: a digit that differs between keys
    // (which digits occur does not depend on the order, so the input tells).
    int active[64 / kDigitBits + 1];
    int passes = 0;
    if (n > 0) {
        std::uint64_t differ = 0;  // bits in which some key differs from the first
        for (std::size_t i = 1; i < n; ++i) differ |= keys[i] ^ keys[0];
        for (int shift = 0; shift < bits; shift += kDigitBits)
            if ((differ >> shift) & (kDigits - 1)) active[passes++] = shift;
    }
    if (passes == 0) {
        for (std::size_t i = 0; i < n; ++i) perm[i] = static_cast<std::uint32_t>(i);
        return;
    }
    std::uint64_t* keyScratch;
    std::uint32_t* indexScratch;
    if (scratch.size() >= scratchBytes(n) &&
        reinterpret_cast<std::uintptr_t>(scratch.data()) % alignof(std::uint64_t) == 0) {
        keyScratch = reinterpret_cast<std::uint64_t*>(scratch.data());
        indexScratch = reinterpret_cast<std::uint32_t*>(scratch.data() + n * sizeof(std::uint64_t));
    } else {
        keys_.resize(n);
        index_.resize(n);
        keyScratch = keys_.data();
        indexScratch = index_.data();
    }
    // One chunk per thread (at least 16k keys each): each chunk's digits are
    // counted, then scattered to their places in chunk order (stable).
    const std::size_t chunks =
        std::clamp<std::size_t>(n / 16384, 1, static_cast<std::size_t>(std::max(1, threadCount())));
    const std::size_t chunkSize = (n + chunks - 1) / chunks;
    counts_.resize(chunks * kDigits);

    // Keys alternate between the input and the scratch (an odd number of
    // passes ends with a copy back); indices between the scratch and perm,
    // so that the last pass writes perm.
    const std::uint64_t* inKeys = keys;
    const std::uint32_t* inIndex = nullptr;  // the identity on the first pass
    for (int p = 0; p < passes; ++p) {
        const int shift = active[p];
        std::uint64_t* outKeys = p % 2 == 0 ? keyScratch : keys;
        std::uint32_t* outIndex = (passes - p) % 2 == 1 ? perm : indexScratch;
        std::fill(counts_.begin(), counts_.end(), 0u);
        parallelForBlocks(n, chunkSize, [&](std::size_t begin, std::size_t end) {
            std::uint32_t* count = counts_.data() + (begin / chunkSize) * kDigits;
            for (std::size_t i = begin; i < end; ++i) ++count[(inKeys[i] >> shift) & (kDigits - 1)];
        });
        std::uint32_t running = 0;  // exclusive offsets in (digit, chunk) order
        for (std::size_t d = 0; d < kDigits; ++d)
            for (std::size_t c = 0; c < chunks; ++c) {
                const std::uint32_t k = counts_[c * kDigits + d];
                counts_[c * kDigits + d] = running;
                running += k;
            }
        parallelForBlocks(n, chunkSize, [&](std::size_t begin, std::size_t end) {
            std::uint32_t* offset = counts_.data() + (begin / chunkSize) * kDigits;
            for (std::size_t i = begin; i < end; ++i) {
                const std::uint32_t to = offset[(inKeys[i] >> shift) & (kDigits - 1)]++;
                outKeys[to] = inKeys[i];
                outIndex[to] = inIndex ? inIndex[i] : static_cast<std::uint32_t>(i);
            }
        });
        inKeys = outKeys;
        inIndex = outIndex;
    }
    if (inKeys != keys) std::copy(inKeys, inKeys + n, keys);
}

}  // namespace pbf::detail
