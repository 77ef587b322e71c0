// Orders of the cells for the cell key: Morton's and Hilbert's curves over
// single cells, Morton over 4x4x4 blocks with rows inside (m-rows4), Morton
// over bricks of 8, 16, 32 cells a side with rows of cells inside
// (brickN), Morton over bricks of blocks with rows of blocks inside
// (blk-rN), pbf's key (bricks of 64 x 32 x 32 cells, rows inside), and
// rows of cells over the whole domain (the dense grid's order, longest axis
// slowest): how the particle order each gives serves the neighbour passes.
// A jittered block of water shaped like the dam break's column (1 : 2 : 1),
// sorted stably by each order's key of its kernel-radius cell; for each:
//   compact    share of 1024-particle blocks whose neighbours' indices span
//              at most 65536 (the CPU search's 16-bit lists)
//   p-compact  share of particles whose neighbours lie within 32768 of it
//   ranges     runs of consecutive particles a particle's 27 cells make
//   distance   mean |i - j| over neighbour pairs (memory distance)
//   pass ms    a density-like sum over CSR neighbour lists (4 passes), the
//              memory-bound shape of the solver's iterations
// Usage: pbf_cell_key_bench [particles]   (default 1000000)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <random>
#include <unordered_map>
#include <vector>

#include "core/cell_key.hpp"

namespace {

using pbf::Vec3;
namespace ck = pbf::cell_key;

struct Result {
    double compact, particleCompact, ranges, distance, passMs;
};

template <class KeyOf>
Result measure(const std::vector<Vec3>& points, float h, KeyOf keyOf) {
    const std::size_t n = points.size();
    const ck::CellFrame frame = ck::CellFrame::over({0, 0, 0}, h);
    std::vector<std::uint64_t> keys(n);
    for (std::size_t i = 0; i < n; ++i) keys[i] = keyOf(frame.coords(points[i]));
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    std::vector<Vec3> x(n);
    for (std::size_t k = 0; k < n; ++k) x[k] = points[order[k]];
    // Cells by coordinates (any curve keeps a cell's particles contiguous).
    std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> cells;
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint64_t m = ck::mortonKey(frame.coords(x[k]));
        auto [it, added] = cells.try_emplace(m, std::uint32_t(k), std::uint32_t(k + 1));
        if (!added) it->second.second = std::uint32_t(k + 1);
    }
    std::vector<std::uint32_t> start(n + 1, 0), index;
    double distance = 0.0, ranges = 0.0;
    std::size_t particleCompact = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const ck::CellCoords c = frame.coords(x[i]);
        std::vector<std::pair<std::uint32_t, std::uint32_t>> spans;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    if ((c.x == 0 && dx < 0) || (c.y == 0 && dy < 0) || (c.z == 0 && dz < 0))
                        continue;
                    const auto it = cells.find(ck::mortonKey(
                        {c.x + std::uint32_t(dx), c.y + std::uint32_t(dy), c.z + std::uint32_t(dz)}));
                    if (it == cells.end()) continue;
                    spans.push_back(it->second);
                    for (std::uint32_t j = it->second.first; j < it->second.second; ++j) {
                        const Vec3 d = x[i] - x[j];
                        if (j != i && dot(d, d) < h * h) {
                            index.push_back(j);
                            distance += std::abs(double(j) - double(i));
                        }
                    }
                }
        start[i + 1] = std::uint32_t(index.size());
        std::sort(spans.begin(), spans.end());
        std::uint32_t lo = std::uint32_t(i), hi = std::uint32_t(i);
        for (std::size_t k = 0; k < spans.size(); ++k) {
            ranges += (k == 0 || spans[k].first != spans[k - 1].second) ? 1.0 : 0.0;
            lo = std::min(lo, spans[k].first);
            hi = std::max(hi, spans[k].second);
        }
        particleCompact += (i - lo <= 32768 && hi - i <= 32768) ? 1 : 0;
    }
    std::size_t compact = 0, blocks = 0;
    for (std::size_t b = 0; b < n; b += 1024, ++blocks) {
        std::uint32_t lo = std::uint32_t(b), hi = std::uint32_t(b);
        for (std::size_t i = b; i < std::min(n, b + 1024); ++i)
            for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
                lo = std::min(lo, index[k]);
                hi = std::max(hi, index[k] + 1);
            }
        compact += hi - lo <= 65536 ? 1 : 0;
    }
    std::vector<float> rho(n, 0.0f);
    const auto t0 = std::chrono::steady_clock::now();
    for (int pass = 0; pass < 4; ++pass)
        for (std::size_t i = 0; i < n; ++i) {
            float sum = 0.0f;
            for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
                const Vec3 d = x[i] - x[index[k]];
                const float q = h * h - dot(d, d);
                sum += q * q * q + 1e-3f * rho[index[k]];
            }
            rho[i] = sum;
        }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return {double(compact) / double(blocks), double(particleCompact) / double(n),
            ranges / double(n), distance / double(index.size()), ms};
}

}  // namespace

int main(int argc, char** argv) {
    const double target = argc > 1 ? std::atof(argv[1]) : 1e6;
    const float spacing = 0.01f, h = 2.0f * spacing;
    const int side = int(std::cbrt(target / 2.0));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> jitter(-0.1f * spacing, 0.1f * spacing);
    std::vector<Vec3> points;
    for (int k = 0; k < side; ++k)
        for (int j = 0; j < 2 * side; ++j)
            for (int i = 0; i < side; ++i)
                points.push_back({0.3f + (float(i) + 0.5f) * spacing + jitter(rng),
                                  0.3f + (float(j) + 0.5f) * spacing + jitter(rng),
                                  0.3f + (float(k) + 0.5f) * spacing + jitter(rng)});
    std::printf("%zu particles, h = 2 spacings\n", points.size());
    std::printf("%-8s %9s %9s %7s %10s %9s\n", "curve", "compact", "p-compact", "ranges",
                "distance", "pass ms");
    const auto print = [](const char* name, const Result& r) {
        std::printf("%-8s %9.3f %9.3f %7.2f %10.0f %9.1f\n", name, r.compact, r.particleCompact,
                    r.ranges, r.distance, r.passMs);
    };
    for (int round = 0; round < 2; ++round) {
        print("morton", measure(points, h, [](ck::CellCoords c) { return ck::mortonKey(c); }));
        print("hilbert", measure(points, h, [](ck::CellCoords c) { return ck::hilbertKey(c); }));
        // Morton order of 4x4x4 blocks, rows of cells (x fastest) inside each.
        print("m-rows4", measure(points, h, [](ck::CellCoords c) {
                  const std::uint64_t block = ck::mortonKey({c.x >> 2, c.y >> 2, c.z >> 2});
                  return block << 6 | (c.z & 3u) << 4 | (c.y & 3u) << 2 | (c.x & 3u);
              }));
        for (const std::uint32_t b : {3u, 4u, 5u}) {
            const std::uint32_t low = (1u << b) - 1u;
            char name[16];
            std::snprintf(name, sizeof name, "brick%u", 1u << b);
            print(name, measure(points, h, [b, low](ck::CellCoords c) {
                      const std::uint64_t brick = ck::mortonKey({c.x >> b, c.y >> b, c.z >> b});
                      return brick << (3 * b) | std::uint64_t(c.y & low) << (2 * b) |
                             std::uint64_t(c.z & low) << b | (c.x & low);
                  }));
        }
        // Morton order of bricks of 2^b 4x4x4 blocks a side, rows of blocks inside a
        // brick (x fastest, y slowest), Morton order of the cells inside a block.
        for (const std::uint32_t b : {2u, 3u, 4u}) {
            const std::uint32_t low = (1u << b) - 1u;
            char name[16];
            std::snprintf(name, sizeof name, "blk-r%u", 1u << b);
            print(name, measure(points, h, [b, low](ck::CellCoords c) {
                      const ck::CellCoords q{c.x >> 2, c.y >> 2, c.z >> 2};
                      const std::uint64_t brick = ck::mortonKey({q.x >> b, q.y >> b, q.z >> b});
                      const std::uint64_t rows = std::uint64_t(q.y & low) << (2 * b) |
                                                 std::uint64_t(q.z & low) << b | (q.x & low);
                      return (brick << (3 * b) | rows) << 6 |
                             ck::mortonKey({c.x & 3u, c.y & 3u, c.z & 3u});
                  }));
        }
        print("pbf key", measure(points, h, [](ck::CellCoords c) { return ck::cellKey(c); }));
        // Rows of cells, the longest axis (y) slowest: the dense grid's order.
        print("rows", measure(points, h, [](ck::CellCoords c) {
                  return std::uint64_t(c.y) << 42 | std::uint64_t(c.z) << 21 | c.x;
              }));
    }
    return 0;
}
