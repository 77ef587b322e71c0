// The GPU backend's cache of temporary buffers (backend/gpu/block_cache.hpp)
// asked from many threads at once, as Thrust's OpenMP merge sort does inside
// its parallel region (cuda-on-cpu). Catches a cache without its lock: two
// threads handed the same block (each fills its block with its own mark and
// finds another's), or the block list grown under a reader (a crash). The
// unlocked cache crashed stable_sort_by_key on a 16-core machine; here,
// on 2 cores, the unlocked cache fails 3 runs of 4 (18 to 19,000 clashes).
#include "backend/gpu/block_cache.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

namespace pbf::test {
namespace {

struct HostMalloc {
    char* operator()(std::size_t n) const { return static_cast<char*>(std::malloc(n)); }
};
struct HostFree {
    void operator()(char* data) const { std::free(data); }
};

TEST(BlockCache, ManyThreadsNeverShareABlock) {
    gpu::BlockCache<HostMalloc, HostFree> cache{HostMalloc{}, HostFree{}};
    // A long list of small free blocks before a few large ones: every
    // request scans the list, so two threads reach the same free block at
    // about the same time (the window an unlocked cache loses).
    std::vector<char*> held;
    for (int k = 0; k < 2000; ++k) held.push_back(cache.allocate(64));
    for (int k = 0; k < 4; ++k) held.push_back(cache.allocate(4096));
    for (char* block : held) cache.deallocate(block, 0);
    constexpr int threads = 8;
    constexpr int rounds = 8000;
    std::atomic<int> clashes{0};
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (int r = 0; r < rounds; ++r) {
                const std::size_t n = 1024 + std::size_t((t * 131 + r * 17) % 3072);
                char* block = cache.allocate(std::ptrdiff_t(n));
                std::memset(block, t + 1, n);
                std::this_thread::yield();
                for (std::size_t k = 0; k < n; ++k)
                    if (block[k] != char(t + 1)) {
                        ++clashes;
                        break;
                    }
                cache.deallocate(block, n);
            }
        });
    for (std::thread& th : pool) th.join();
    EXPECT_EQ(clashes.load(), 0) << "two threads were handed the same block";
}

}  // namespace
}  // namespace pbf::test
