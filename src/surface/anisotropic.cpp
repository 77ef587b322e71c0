// Anisotropic kernels (Yu & Turk 2013) and their iso-surface as a level set
// (method and equations in include/pbf/surface/anisotropic.hpp).
#include "pbf/surface/anisotropic.hpp"

#include <openvdb/math/Mat3.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>

#include "anisotropic_grid.hpp"
#include "sorted_cells.hpp"

namespace pbf::surface {

namespace {

// 315 / (64 pi): the poly6 profile (1 - q^2)^3 integrates to 1 over the unit ball.
constexpr double kPoly6 = 315.0 / (64.0 * std::numbers::pi);
// No semi-axis longer than this many h: a particle in a line of particles
// gets about 1.5 h; the cap only bounds the boxes the rasterisation visits
// (the paper evaluates the field without such boxes).
constexpr double kMaxStretch = 2.0;

// The covariance eigenvalue of a particle inside the fluid: a full lattice
// ball (spacing 2 r) of radius R around it with the weights of eq. 11. Its
// inverse is k_s, so that such a particle gets the isotropic kernel.
double bulkEigenvalue(double neighborRadius) {  // in units of r
    const int n = int(std::ceil(neighborRadius / 2.0));
    double weights = 0.0, moments = 0.0;
    for (int k = -n; k <= n; ++k)
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i) {
                const double d2 = 4.0 * (i * i + j * j + k * k);
                if (d2 >= neighborRadius * neighborRadius) continue;
                const double w = 1.0 - std::pow(std::sqrt(d2) / neighborRadius, 3.0);
                weights += w;
                moments += w * d2 / 3.0;
            }
    return moments / weights;
}

Ellipsoid makeEllipsoid(Vec3 centre, const double a[3], const openvdb::math::Mat3d& q,
                        double volume) {
    Ellipsoid e;
    e.centre = centre;
    for (int k = 0; k < 3; ++k)
        e.axes[std::size_t(k)] = {float(q(0, k) * a[k]), float(q(1, k) * a[k]),
                                  float(q(2, k) * a[k])};
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) {
            double g = 0.0;
            for (int k = 0; k < 3; ++k) g += q(row, k) * q(col, k) / a[k];
            e.g[std::size_t(3 * row + col)] = float(g);
        }
    const auto extent = [&](int row) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k) s += (q(row, k) * a[k]) * (q(row, k) * a[k]);
        return float(std::sqrt(s));
    };
    e.halfExtent = {extent(0), extent(1), extent(2)};
    e.peak = float(volume * kPoly6 / (a[0] * a[1] * a[2]));
    return e;
}

void requireValid(const SurfaceParams& params) {
    if (const std::string problem = validate(params); !problem.empty())
        throw std::invalid_argument(problem);
}

}  // namespace

float kernelValue(const Ellipsoid& e, Vec3 x) {
    const Vec3 d = x - e.centre;
    const auto& g = e.g;
    const float q0 = g[0] * d.x + g[1] * d.y + g[2] * d.z;
    const float q1 = g[3] * d.x + g[4] * d.y + g[5] * d.z;
    const float q2 = g[6] * d.x + g[7] * d.y + g[8] * d.z;
    const float t = 1.0f - (q0 * q0 + q1 * q1 + q2 * q2);
    return t > 0.0f ? e.peak * t * t * t : 0.0f;
}

std::vector<Ellipsoid> computeEllipsoids(std::span<const Vec3> positions,
                                         const SurfaceParams& params) {
    requireValid(params);
    const double r = params.particleRadius;
    const double h = params.kernelRadius * r;
    const double radius = params.neighborRadius * r;
    const double ks = 1.0 / (bulkEigenvalue(params.neighborRadius) * r * r);
    const double lambda = params.centreSmoothing;
    const double volume = 8.0 * r * r * r;  // (2 r)^3 of water per particle
    std::vector<Ellipsoid> out(positions.size());
    if (positions.empty()) return out;
    const detail::SortedCells cells(positions, radius);

    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, positions.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const Vec3 xi = positions[i];
            // Sums relative to x_i (double): the mean and the covariance of
            // metre-scale coordinates would lose the millimetre detail.
            double sw = 0.0, m[3] = {0, 0, 0}, c[6] = {0, 0, 0, 0, 0, 0};
            int count = 0;
            cells.forEachNear(xi, [&](std::uint32_t j) {
                const Vec3 d = positions[j] - xi;
                const double d2 = double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z;
                if (d2 >= radius * radius) return;
                const double w = 1.0 - std::pow(std::sqrt(d2) / radius, 3.0);  // eq. 11
                if (j != i) ++count;
                sw += w;
                m[0] += w * d.x, m[1] += w * d.y, m[2] += w * d.z;
                c[0] += w * d.x * d.x, c[1] += w * d.x * d.y, c[2] += w * d.x * d.z;
                c[3] += w * d.y * d.y, c[4] += w * d.y * d.z, c[5] += w * d.z * d.z;
            });
            for (double& v : m) v /= sw;  // x_w - x_i (eq. 10)
            // eq. 6: the smoothed centre.
            const Vec3 centre{float(xi.x + lambda * m[0]), float(xi.y + lambda * m[1]),
                              float(xi.z + lambda * m[2])};
            openvdb::math::Mat3d q = openvdb::math::Mat3d::identity();
            double a[3];
            const auto isotropic = [&] {
                a[0] = a[1] = a[2] = params.isolatedScale * h;
                out[i] = makeEllipsoid(centre, a, q, volume);
            };
            if (count < params.anisotropyMinNeighbors) {
                isotropic();
                out[i].neighbors = count;
                continue;
            }
            // eq. 9: E[d d^T] - mean mean^T, i.e. the covariance about x_w.
            const openvdb::math::Mat3d cov(
                c[0] / sw - m[0] * m[0], c[1] / sw - m[0] * m[1], c[2] / sw - m[0] * m[2],
                c[1] / sw - m[0] * m[1], c[3] / sw - m[1] * m[1], c[4] / sw - m[1] * m[2],
                c[2] / sw - m[0] * m[2], c[4] / sw - m[1] * m[2], c[5] / sw - m[2] * m[2]);
            openvdb::math::Mat3d vectors;
            openvdb::math::Vec3d values;
            if (!openvdb::math::diagonalizeSymmetricMatrix(cov, vectors, values) ||
                !(std::max({values[0], values[1], values[2]}) > 0.0)) {
                isotropic();
                out[i].neighbors = count;
                continue;
            }
            // Eigenvalues largest first, with their eigenvectors (columns).
            int order[3] = {0, 1, 2};
            std::sort(order, order + 3, [&](int x, int y) { return values[x] > values[y]; });
            const double s1 = values[order[0]];
            for (int k = 0; k < 3; ++k) {
                const int o = order[k];
                // eq. 13: no axis below s1 / k_r; then k_s scales the
                // eigenvalues to axis lengths in units of h.
                const double s = std::max(values[o], s1 / params.maxAnisotropy);
                a[k] = std::min(h * ks * s, kMaxStretch * h);
                for (int row = 0; row < 3; ++row) q(row, k) = vectors(row, o);
            }
            out[i] = makeEllipsoid(centre, a, q, volume);
            out[i].neighbors = count;
        }
    });
    return out;
}

float anisotropicIsoValue(const SurfaceParams& params) {
    requireValid(params);
    // The iso-value depends on the shape parameters only (all lengths scale
    // with r), so the calibration runs at r = 1 and is cached per shape.
    using Key = std::array<float, 6>;
    const Key key{params.kernelRadius,    params.neighborRadius,
                  params.centreSmoothing, params.maxAnisotropy,
                  params.isolatedScale,   float(params.anisotropyMinNeighbors)};
    static std::mutex mutex;
    static std::map<Key, float> cache;
    {
        const std::lock_guard lock(mutex);
        if (const auto it = cache.find(key); it != cache.end()) return it->second;
    }
    SurfaceParams unit = params;
    unit.particleRadius = 1.0f;
    // A flat lattice layer (spacing 2, top centres at y = 0) wide and deep
    // enough that every kernel reaching the sample points has a full
    // neighbourhood below and beside it.
    const double reach = kMaxStretch * params.kernelRadius + params.neighborRadius;
    const int n = int(std::ceil(reach / 2.0)) + 1;
    std::vector<Vec3> layer;
    for (int k = 0; k <= n; ++k)
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i)
                layer.push_back({2.0f * float(i), -2.0f * float(k), 2.0f * float(j)});
    const std::vector<Ellipsoid> kernels = computeEllipsoids(layer, unit);
    // phi one radius above the top centres, averaged over a lattice cell:
    // the surface is to lie there.
    constexpr int kSamples = 8;
    double sum = 0.0;
    for (int j = 0; j < kSamples; ++j)
        for (int i = 0; i < kSamples; ++i) {
            const Vec3 x{2.0f * (float(i) + 0.5f) / kSamples, 1.0f,
                         2.0f * (float(j) + 0.5f) / kSamples};
            double phi = 0.0;
            for (const Ellipsoid& e : kernels) phi += kernelValue(e, x);
            sum += phi;
        }
    const float iso = float(sum / (kSamples * kSamples));
    const std::lock_guard lock(mutex);
    cache.emplace(key, iso);
    return iso;
}

namespace detail {

openvdb::FloatGrid::Ptr anisotropicLevelSet(std::span<const Vec3> positions,
                                            const SurfaceParams& params, double voxel,
                                            float halfWidth) {
    using Leaf = openvdb::FloatTree::LeafNodeType;
    const std::vector<Ellipsoid> kernels = computeEllipsoids(positions, params);
    const float iso = anisotropicIsoValue(params);
    const double inverse = 1.0 / voxel;

    // Voxel boxes of the kernels (voxel centres at integer multiples of the
    // voxel size, as in OpenVDB's linear transform).
    struct Box {
        openvdb::Coord lo, hi;
    };
    std::vector<Box> boxes(kernels.size());
    std::vector<std::size_t> leafCounts(kernels.size() + 1, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kernels.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const Ellipsoid& e = kernels[i];
            const auto lo = [&](float c, float x) { return int(std::ceil((c - x) * inverse)); };
            const auto hi = [&](float c, float x) { return int(std::floor((c + x) * inverse)); };
            boxes[i].lo = {lo(e.centre.x, e.halfExtent.x), lo(e.centre.y, e.halfExtent.y),
                           lo(e.centre.z, e.halfExtent.z)};
            boxes[i].hi = {hi(e.centre.x, e.halfExtent.x), hi(e.centre.y, e.halfExtent.y),
                           hi(e.centre.z, e.halfExtent.z)};
            const openvdb::Coord a = boxes[i].lo >> 3, b = boxes[i].hi >> 3;
            leafCounts[i + 1] = std::size_t(b.x() - a.x() + 1) * std::size_t(b.y() - a.y() + 1) *
                                std::size_t(b.z() - a.z() + 1);
        }
    });
    std::partial_sum(leafCounts.begin(), leafCounts.end(), leafCounts.begin());
    // (leaf, kernel) pairs, sorted: each leaf sums its kernels in index order,
    // so the field has the same bits for any thread count.
    struct Pair {
        openvdb::Coord leaf;
        std::uint32_t kernel;
        bool operator<(const Pair& o) const {
            return leaf != o.leaf ? leaf < o.leaf : kernel < o.kernel;
        }
    };
    std::vector<Pair> pairs(leafCounts.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kernels.size()), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const openvdb::Coord a = boxes[i].lo >> 3, b = boxes[i].hi >> 3;
            std::size_t k = leafCounts[i];
            for (int z = a.z(); z <= b.z(); ++z)
                for (int y = a.y(); y <= b.y(); ++y)
                    for (int x = a.x(); x <= b.x(); ++x)
                        pairs[k++] = {openvdb::Coord(x, y, z) << 3, std::uint32_t(i)};
        }
    });
    tbb::parallel_sort(pairs.begin(), pairs.end());
    std::vector<std::size_t> starts;
    for (std::size_t k = 0; k < pairs.size(); ++k)
        if (k == 0 || pairs[k].leaf != pairs[k - 1].leaf) starts.push_back(k);
    starts.push_back(pairs.size());

    // The field stored as -phi (inside negative, as level sets are), with
    // background 0 = no water.
    std::vector<Leaf*> leaves(starts.size() - 1, nullptr);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const auto& range) {
        for (std::size_t l = range.begin(); l != range.end(); ++l) {
            const openvdb::Coord origin = pairs[starts[l]].leaf;
            auto* leaf = new Leaf(origin, 0.0f, false);
            for (std::size_t k = starts[l]; k < starts[l + 1]; ++k) {
                const Ellipsoid& e = kernels[pairs[k].kernel];
                const Box& box = boxes[pairs[k].kernel];
                const openvdb::Coord lo = openvdb::Coord::maxComponent(box.lo, origin);
                const openvdb::Coord hi =
                    openvdb::Coord::minComponent(box.hi, origin.offsetBy(Leaf::DIM - 1));
                for (int z = lo.z(); z <= hi.z(); ++z)
                    for (int y = lo.y(); y <= hi.y(); ++y)
                        for (int x = lo.x(); x <= hi.x(); ++x) {
                            const float value = kernelValue(
                                e, Vec3{float(x * voxel), float(y * voxel), float(z * voxel)});
                            if (value == 0.0f) continue;
                            const openvdb::Index offset =
                                Leaf::coordToOffset(openvdb::Coord(x, y, z));
                            leaf->setValueOn(offset, leaf->getValue(offset) - value);
                        }
            }
            leaves[l] = leaf;
        }
    });
    openvdb::FloatGrid::Ptr field = openvdb::FloatGrid::create(0.0f);
    field->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    for (Leaf* leaf : leaves) field->tree().addLeaf(leaf);
    // The iso-surface phi = iso as a narrow-band signed distance field
    // (OpenVDB meshes the iso-surface and rebuilds the distances from it).
    openvdb::FloatGrid::Ptr levelSet = openvdb::tools::levelSetRebuild(*field, -iso, halfWidth);
    levelSet->setName("surface");
    return levelSet;
}

}  // namespace detail

}  // namespace pbf::surface
