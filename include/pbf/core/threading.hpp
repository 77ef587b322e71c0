// Thread count used by every parallel pass of the library.
//
// All passes are deterministic: each parallel loop writes only its own
// particle and reductions are combined in a fixed order, so results are
// bit-identical whatever the thread count.
#pragma once

namespace pbf {

// Sets the number of worker threads (>= 1). Defaults to the OpenMP default
// (usually the number of cores).
void setThreadCount(int threads);
int threadCount();
// Number of hardware threads the machine offers.
int hardwareThreadCount();

}  // namespace pbf
