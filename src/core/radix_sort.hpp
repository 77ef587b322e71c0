// Stable least-significant-digit radix sort of 64-bit keys (private header):
// the order of the particles by cell key in the CPU search. Parallel over
// fixed chunks of the input; a stable sort's result is unique, so it is the
// same whatever the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pbf::detail {

class RadixSort {
  public:
    // Sorts the n keys by their low `bits` bits (the rest must be zero),
    // stably: writes the keys in increasing order to sortedKeys and, for
    // each sorted place, the input index it came from to perm. Passes whose
    // digit is the same for every key are skipped. Scratch is kept between
    // calls (no allocation once n stops growing).
    void sort(const std::uint64_t* keys, std::size_t n, int bits, std::uint64_t* sortedKeys,
              std::uint32_t* perm);
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
