// Google Benchmark of the neighbour search: sort by cell + reorder + lists,
// on a jittered lattice (fluid-like density) at several sizes.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "backend/cpu/neighbor_search.hpp"
#include "pbf/core/particles.hpp"

namespace {

pbf::ParticleStore jitteredCube(std::size_t target, float spacing) {
    const auto side = static_cast<std::size_t>(std::cbrt(double(target)));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> jitter(-0.1f * spacing, 0.1f * spacing);
    pbf::ParticleStore p;
    p.reserve(side * side * side);
    for (std::size_t k = 0; k < side; ++k)
        for (std::size_t j = 0; j < side; ++j)
            for (std::size_t i = 0; i < side; ++i)
                p.add({(float(i) + 0.5f) * spacing + jitter(rng),
                       (float(j) + 0.5f) * spacing + jitter(rng),
                       (float(k) + 0.5f) * spacing + jitter(rng)},
                      {}, 1000.0f);
    return p;
}

void BM_NeighborSearch(benchmark::State& state) {
    const float spacing = 0.02f;
    pbf::ParticleStore p = jitteredCube(static_cast<std::size_t>(state.range(0)), spacing);
    const float extent = std::cbrt(float(p.size())) * spacing + spacing;
    pbf::NeighborSearch search({{0, 0, 0}, {extent, extent, extent}}, 2.0f * spacing);
    std::vector<std::uint32_t> perm;
    for (auto _ : state) {
        search.sortByCell(p.predicted, perm);
        p.reorder(perm);
        search.buildNeighborLists(p.predicted);
        benchmark::DoNotOptimize(search.totalNeighborCount());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long long>(p.size()));
    state.counters["neighbors"] = double(search.totalNeighborCount()) / double(p.size());
}
BENCHMARK(BM_NeighborSearch)->Arg(16000)->Arg(128000)->Arg(1000000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
