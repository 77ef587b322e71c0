// Stable least-significant-digit radix sort of 64-bit keys (private header):
// the order of the particles by cell key in the CPU search. Parallel over
// fixed chunks of the input; a stable sort's result is unique, so it is the
// same whatever the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pbf::detail {

class RadixSort {
  public:
    // Sorts the n keys in place by their low `bits` bits (the rest must be
    // zero), stably, and writes for each sorted place the input index it
    // came from to perm. Passes whose digit is the same for every key are
    // skipped. The passes alternate between the keys and a scratch of n keys
    // and n indices: `scratch` (at least scratchBytes(n), 8-byte aligned,
    // whose contents the sort overwrites) where the caller has such memory
    // idle, else the sort's own, kept between calls (no allocation once n
    // stops growing).
    void sort(std::uint64_t* keys, std::size_t n, int bits, std::uint32_t* perm,
              std::span<std::byte> scratch = {});
    static constexpr std::size_t scratchBytes(std::size_t n) {
        return n * (sizeof(std::uint64_t) + sizeof(std::uint32_t));
    }
    std::size_t memoryBytes() const {
        return sizeof(std::uint64_t) * keys_.capacity() +
               sizeof(std::uint32_t) * (index_.capacity() + counts_.capacity());
    }

  private:
    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> index_;
    std::vector<std::uint32_t> counts_;  // [chunk][digit]
};

}  // namespace pbf::detail
