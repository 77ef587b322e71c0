#include "pbf/core/threading.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>

namespace pbf {
namespace {
std::atomic<int> gThreads{0};  // 0: not set, use the OpenMP default
}

void setThreadCount(int threads) {
    gThreads = std::max(1, threads);
}

int threadCount() {
    const int t = gThreads.load();
    return t > 0 ? t : omp_get_max_threads();
}

int hardwareThreadCount() {
    return omp_get_num_procs();
}

}  // namespace pbf
