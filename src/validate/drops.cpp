#include "validate/drops.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>

#include "backend/reference/neighbor_grid.hpp"

namespace pbf::validation::detail {

WorldDef waterWorld(float radius, float domainSide, float surfaceTension) {
    WorldDef def;
    const float half = 0.5f * domainSide;
    def.simulation.domain = {{-half, -half, -half}, {half, half, half}};
    def.simulation.gravity = {0.0f, 0.0f, 0.0f};
    def.simulation.particleRadius = radius;
    def.simulation.fluid.surfaceTension = surfaceTension;
    return def;
}

std::vector<Vec3> latticeSites(const WorldDef& def, const Aabb& bounds, const Vec3& origin,
                               const std::function<bool(const Vec3&)>& inside) {
    const double d = def.simulation.particleSpacing();
    std::vector<Vec3> sites;
    const auto first = [&](float lo, float o) { return int(std::ceil((lo - o) / d)); };
    const auto last = [&](float hi, float o) { return int(std::floor((hi - o) / d)); };
    for (int k = first(bounds.min.z, origin.z); k <= last(bounds.max.z, origin.z); ++k)
        for (int j = first(bounds.min.y, origin.y); j <= last(bounds.max.y, origin.y); ++j)
            for (int i = first(bounds.min.x, origin.x); i <= last(bounds.max.x, origin.x); ++i) {
                const Vec3 x{float(origin.x + i * d), float(origin.y + j * d),
                             float(origin.z + k * d)};
                if (inside(x)) sites.push_back(x);
            }
    return sites;
}

Vec3 latticeShift(int k) {
    constexpr double g = 1.2207440846057595;  // g^4 = g + 1 (Roberts' phi for 3 dimensions)
    const auto fraction = [&](int power) {
        return float(std::fmod(double(k) / std::pow(g, power), 1.0));
    };
    return {fraction(1), fraction(2), fraction(3)};
}

World worldOf(WorldDef def, const std::vector<Vec3>& sites) {
    const float r = def.simulation.particleRadius;
    const Vec3 corner{r, r, r};
    def.fluidBlocks = {{{sites.front() - corner, sites.front() + corner}, {}}};
    World world(def);
    const std::vector<Vec3> rest(sites.begin() + 1, sites.end());
    world.addParticles(rest, std::vector<Vec3>(rest.size()));
    return world;
}

std::vector<Vec3> positions(const World& world) {
    const ParticleStore& p = world.particles();
    std::vector<Vec3> x(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) x[i] = p.position.get(i);
    return x;
}

Vec3 centroid(const std::vector<Vec3>& x) {
    double s[3] = {0, 0, 0};
    for (const Vec3& p : x)
        for (int a = 0; a < 3; ++a) s[a] += p[a];
    const double n = double(std::max<std::size_t>(x.size(), 1));
    return {float(s[0] / n), float(s[1] / n), float(s[2] / n)};
}

namespace {

Aabb boundsOf(const std::vector<Vec3>& x, float margin) {
    Aabb box{x.front(), x.front()};
    for (const Vec3& p : x) {
        box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
        box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
    }
    const Vec3 m{margin, margin, margin};
    return {box.min - m, box.max + m};
}

}  // namespace

namespace {

// The root (a member index) of each particle's connected component, the
// particles linked closer than `link`: union-find over the neighbour grid.
std::vector<std::uint32_t> clusterRoots(const std::vector<Vec3>& x, float link) {
    reference::NeighborGrid grid(boundsOf(x, link), link);
    grid.build(x);
    std::vector<std::uint32_t> parent(x.size());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto root = [&](std::uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (std::size_t i = 0; i < x.size(); ++i)
        for (const std::uint32_t j : grid.neighbors(i)) parent[root(std::uint32_t(i))] = root(j);
    for (std::size_t i = 0; i < x.size(); ++i) parent[i] = root(std::uint32_t(i));
    return parent;
}

}  // namespace

std::size_t clusterCount(const std::vector<Vec3>& x, float link) {
    if (x.empty()) return 0;
    const std::vector<std::uint32_t> roots = clusterRoots(x, link);
    std::size_t count = 0;
    for (std::size_t i = 0; i < x.size(); ++i) count += roots[i] == i;
    return count;
}

std::vector<std::size_t> clusterSizes(const std::vector<Vec3>& x, float link) {
    if (x.empty()) return {};
    const std::vector<std::uint32_t> roots = clusterRoots(x, link);
    std::vector<std::size_t> size(x.size(), 0);
    for (const std::uint32_t r : roots) ++size[r];
    std::vector<std::size_t> sizes;
    for (const std::size_t n : size)
        if (n > 0) sizes.push_back(n);
    std::sort(sizes.begin(), sizes.end(), std::greater<>());
    return sizes;
}

std::vector<Vec3> largestCluster(const std::vector<Vec3>& x, float link) {
    if (x.empty()) return {};
    const std::vector<std::uint32_t> roots = clusterRoots(x, link);
    std::vector<std::size_t> size(x.size(), 0);
    for (const std::uint32_t r : roots) ++size[r];
    const std::size_t largest =
        std::size_t(std::max_element(size.begin(), size.end()) - size.begin());
    std::vector<Vec3> kept;
    kept.reserve(size[largest]);
    for (std::size_t i = 0; i < x.size(); ++i)
        if (roots[i] == largest) kept.push_back(x[i]);
    return kept;
}

std::vector<double> nearestNeighborDistances(const std::vector<Vec3>& x, float reach) {
    std::vector<double> nearest(x.size(), double(reach));
    if (x.size() < 2) return nearest;
    reference::NeighborGrid grid(boundsOf(x, reach), reach);
    grid.build(x);
    for (std::size_t i = 0; i < x.size(); ++i)
        for (const std::uint32_t j : grid.neighbors(i))
            nearest[i] = std::min(nearest[i], double(length(x[i] - x[j])));
    return nearest;
}

double smallestPairDistance(const std::vector<Vec3>& x, float reach) {
    double smallest = std::numeric_limits<double>::infinity();
    if (x.size() < 2) return smallest;
    reference::NeighborGrid grid(boundsOf(x, reach), reach);
    grid.build(x);
    for (std::size_t i = 0; i < x.size(); ++i)
        for (const std::uint32_t j : grid.neighbors(i))
            smallest = std::min(smallest, double(length(x[i] - x[j])));
    return std::min(smallest, double(reach));
}

}  // namespace pbf::validation::detail
