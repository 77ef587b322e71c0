// Buffers kept between calls for Thrust's temporary storage (the sort's,
// the reductions'): a block is handed out again once it is given back, so
// no allocation happens inside a step once the sizes have settled (a
// cudaMalloc and cudaFree per sort would cost more than the sort).
//
// Thread-safe: on the GPU only the host thread asks, but Thrust's OpenMP
// system (cuda-on-cpu) allocates its merge sort's temporaries inside its
// parallel region, one per thread. Unlocked, two threads walked and grew the
// block list at once: seen as a crash in stable_sort_by_key on a 16-core
// machine, never on 2 cores (tests/backend/gpu/block_cache_test.cpp).
#pragma once
#include <cstddef>
#include <mutex>
#include <vector>

namespace pbf::gpu {

// Alloc and Free: how a block is made and released (device memory on the
// GPU, host memory in the test), char* (std::size_t) and void (char*).
template <class Alloc, class Free>
class BlockCache {
  public:
    using value_type = char;
    BlockCache(Alloc alloc, Free free) : alloc_(alloc), free_(free) {}
    BlockCache(const BlockCache&) = delete;
    BlockCache& operator=(const BlockCache&) = delete;
    ~BlockCache() {
        for (const Block& b : blocks_) free_(b.data);
    }
    char* allocate(std::ptrdiff_t bytes) {
        const std::size_t n = static_cast<std::size_t>(bytes);
        const std::lock_guard<std::mutex> lock(mutex_);
        for (Block& b : blocks_)
            if (!b.used && b.size >= n) {
                b.used = true;
                return b.data;
            }
        char* data = alloc_(n);
        blocks_.push_back({data, n, true});
        return data;
    }
    void deallocate(char* data, std::size_t) {
        const std::lock_guard<std::mutex> lock(mutex_);
        for (Block& b : blocks_)
            if (b.data == data) b.used = false;
    }
    // Bytes held (diagnostics: the device memory the World reports).
    std::size_t bytes() const {
        const std::lock_guard<std::mutex> lock(mutex_);
        std::size_t total = 0;
        for (const Block& b : blocks_) total += b.size;
        return total;
    }

  private:
    struct Block {
        char* data;
        std::size_t size;
        bool used;
    };
    Alloc alloc_;
    Free free_;
    mutable std::mutex mutex_;
    std::vector<Block> blocks_;
};

}  // namespace pbf::gpu
