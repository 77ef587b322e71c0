// Diffuse particles (Ihmsen et al. 2012; method and equations in
// include/pbf/surface/diffuse.hpp).
#include "pbf/surface/diffuse.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sorted_cells.hpp"
#include "vdb_points_detail.hpp"

namespace pbf::surface {

namespace {

// Counter-based random numbers (splitmix64 finaliser): the n-th draw of a
// fluid particle in a substep is a function of the key alone, so the
// result does not depend on which thread makes it.
std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
struct Random {
    std::uint64_t state;
    float next() {  // [0, 1)
        state = mix(state);
        return float(state >> 40) * (1.0f / 16777216.0f);
    }
};

// eq. 1: the potential I mapped to [0, 1] between tmin and tmax.
double clampPotential(double value, double tmin, double tmax) {
    return (std::min(value, tmax) - std::min(value, tmin)) / (tmax - tmin);
}

// eq. 3: the paper's radially symmetric weight.
double weight(double distance, double h) {
    return distance < h ? 1.0 - distance / h : 0.0;
}

}  // namespace

std::size_t DiffuseParticles::count(DiffuseType t) const {
    return std::size_t(std::count(type.begin(), type.end(), t));
}

std::string validate(const DiffuseParams& p) {
    if (!(p.particleRadius > 0.0f && std::isfinite(p.particleRadius)))
        return "radius: the particle radius must be positive, got " +
               std::to_string(p.particleRadius);
    if (!(p.kernelRadius >= 2.0f && p.kernelRadius <= 8.0f))
        return "kernel-radius: must be in [2, 8] particle radii, got " +
               std::to_string(p.kernelRadius);
    if (p.substeps < 1 || p.substeps > 100)
        return "substeps: must be in [1, 100], got " + std::to_string(p.substeps);
    const auto range = [](float lo, float hi) {
        return lo >= 0.0f && hi > lo && std::isfinite(hi);
    };
    if (!range(p.trappedAirMin, p.trappedAirMax)) return "trapped-air: need 0 <= min < max";
    if (!range(p.waveCrestMin, p.waveCrestMax)) return "wave-crest: need 0 <= min < max";
    if (!range(p.energyMin, p.energyMax)) return "energy: need 0 <= min < max";
    if (!(p.trappedAirRate >= 0.0f && p.waveCrestRate >= 0.0f && p.trappedAirRate <= 1e5f &&
          p.waveCrestRate <= 1e5f))
        return "rate: emission rates must be in [0, 1e5] per second";
    if (!range(p.lifetimeMin, p.lifetimeMax)) return "lifetime: need 0 <= min < max";
    if (p.sprayMaxNeighbors < 0 || p.bubbleMinNeighbors <= p.sprayMaxNeighbors)
        return "neighbors: need 0 <= spray maximum < bubble minimum";
    if (!(p.buoyancy >= 0.0f && p.buoyancy <= 100.0f)) return "buoyancy: must be in [0, 100]";
    if (!(p.drag >= 0.0f && p.drag <= 1.0f)) return "drag: must be in [0, 1]";
    return {};
}

DiffuseSimulator::DiffuseSimulator(const DiffuseParams& params) : params_(params) {
    if (const std::string problem = validate(params); !problem.empty())
        throw std::invalid_argument(problem);
}

void DiffuseSimulator::advance(int frame, const ParticleFrame& from, const ParticleFrame& to,
                               double seconds) {
    const auto started = std::chrono::steady_clock::now();
    const DiffuseParams& p = params_;
    const double h = double(p.kernelRadius) * p.particleRadius;
    const int substeps = p.substeps;
    const double dt = seconds / substeps;
    const std::size_t n = to.position.size();
    if (to.velocity.size() != n || from.velocity.size() != from.position.size())
        throw std::invalid_argument("diffuse particles need the fluid's velocities (vx vy vz)");

    // The fluid of `to` matched by id to `from` (both in id order; a
    // particle emitted during the frame takes its `to` state throughout).
    std::vector<std::size_t> previous(n, SIZE_MAX);
    for (std::size_t i = 0, k = 0; i < n; ++i) {
        const std::uint64_t id = to.id.empty() ? std::uint64_t(i) : to.id[i];
        while (k < from.position.size() && (from.id.empty() ? std::uint64_t(k) : from.id[k]) < id)
            ++k;
        if (k < from.position.size() && (from.id.empty() ? std::uint64_t(k) : from.id[k]) == id)
            previous[i] = k;
    }
    std::vector<Vec3> x(n), v(n), normal(n);
    std::vector<char> surface(n);
    std::vector<std::uint32_t> emitted(n + 1);

    for (int s = 0; s < substeps; ++s) {
        const float t = (float(s) + 0.5f) / float(substeps);
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t k = previous[i];
            x[i] = k == SIZE_MAX ? to.position[i]
                                 : from.position[k] + t * (to.position[i] - from.position[k]);
            v[i] = k == SIZE_MAX ? to.velocity[i]
                                 : from.velocity[k] + t * (to.velocity[i] - from.velocity[k]);
        }
        if (n == 0) break;
        const detail::SortedCells cells(x, h);
        Vec3 lo = x[0], hi = x[0];
        for (const Vec3& q : x) {
            lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
            hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
        }
        const float margin = float(h);
        lo = lo - Vec3{margin, margin, margin};
        hi = hi + Vec3{margin, margin, margin};

        // Surface normals: the direction away from the neighbours (the
        // colour field's gradient with the weight of eq. 3); a particle
        // whose neighbours surround it evenly is not at the surface.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                double gx = 0, gy = 0, gz = 0, sum = 0;
                cells.forEachNear(x[i], [&](std::uint32_t j) {
                    const Vec3 d = x[i] - x[j];
                    const double len = length(d);
                    if (j == i || len >= h || len == 0.0) return;
                    const double w = weight(len, h);
                    gx += w * d.x / len, gy += w * d.y / len, gz += w * d.z / len;
                    sum += w;
                });
                const double g = std::sqrt(gx * gx + gy * gy + gz * gz);
                surface[i] = sum > 0.0 && g > 0.25 * sum;
                normal[i] =
                    g > 0.0 ? Vec3{float(gx / g), float(gy / g), float(gz / g)} : Vec3{0, 0, 0};
            }
        });

        // Potentials and the number each fluid particle emits (eq. 1-8).
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const double speed = length(v[i]);
                const double energy = clampPotential(0.5 * speed * speed, p.energyMin, p.energyMax);
                emitted[i + 1] = 0;
                if (energy <= 0.0) continue;  // eq. 8 multiplies by I_k
                double trapped = 0.0, crest = 0.0;
                const Vec3 vhat = speed > 0.0 ? v[i] * float(1.0 / speed) : Vec3{0, 0, 0};
                cells.forEachNear(x[i], [&](std::uint32_t j) {
                    const Vec3 d = x[i] - x[j];
                    const double len = length(d);
                    if (j == i || len >= h || len == 0.0) return;
                    const double w = weight(len, h);
                    const Vec3 dv = v[i] - v[j];
                    const double dvLen = length(dv);
                    if (dvLen > 0.0)  // eq. 2
                        trapped += dvLen * (1.0 - dot(dv, d) / (dvLen * len)) * w;
                    // eq. 4-5: convex where the neighbour behind has a
                    // different normal.
                    if (surface[i] && surface[j] && dot(x[j] - x[i], normal[i]) < 0.0f)
                        crest += (1.0 - dot(normal[i], normal[j])) * w;
                });
                if (!surface[i] || dot(vhat, normal[i]) < 0.6f) crest = 0.0;  // eq. 6
                const double expected =
                    energy *
                    (p.trappedAirRate * clampPotential(trapped, p.trappedAirMin, p.trappedAirMax) +
                     p.waveCrestRate * clampPotential(crest, p.waveCrestMin, p.waveCrestMax)) *
                    dt;
                const std::uint64_t id = to.id.empty() ? std::uint64_t(i) : to.id[i];
                Random rng{mix(p.seed ^
                               mix((std::uint64_t(frame) << 40) ^ (std::uint64_t(s) << 32) ^ id))};
                const double whole = std::floor(expected);
                emitted[i + 1] = std::uint32_t(whole) + (rng.next() < expected - whole ? 1u : 0u);
            }
        });

        // Advect the existing diffuse particles by their type (section 5).
        DiffuseParticles& d = particles_;
        std::vector<char> keep(d.size(), 1);
        const Vec3 g = p.gravity;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, d.size()), [&](const auto& range) {
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
                double wsum = 0.0, ux = 0, uy = 0, uz = 0;
                cells.forEachNear(d.position[k], [&](std::uint32_t j) {
                    const double w = weight(length(d.position[k] - x[j]), h);
                    if (w <= 0.0) return;
                    wsum += w, ux += w * v[j].x, uy += w * v[j].y, uz += w * v[j].z;
                });
                const Vec3 fluid = wsum > 0.0
                                       ? Vec3{float(ux / wsum), float(uy / wsum), float(uz / wsum)}
                                       : Vec3{0, 0, 0};
                const float step = float(dt);
                switch (d.type[k]) {
                    case DiffuseType::spray:  // ballistic
                        d.velocity[k] = d.velocity[k] + step * g;
                        break;
                    case DiffuseType::foam:  // eq. 12: carried by the fluid
                        d.velocity[k] = fluid;
                        d.lifetime[k] -= step;
                        break;
                    case DiffuseType::bubble:  // eq. 11: buoyancy and drag
                        d.velocity[k] = d.velocity[k] - step * p.buoyancy * g +
                                        p.drag * (fluid - d.velocity[k]);
                        break;
                }
                d.position[k] = d.position[k] + step * d.velocity[k];
                const Vec3 q = d.position[k];
                if (d.lifetime[k] <= 0.0f || q.x < lo.x || q.y < lo.y || q.z < lo.z || q.x > hi.x ||
                    q.y > hi.y || q.z > hi.z)
                    keep[k] = 0;
            }
        });
        std::size_t kept = 0;
        for (std::size_t k = 0; k < d.size(); ++k) {
            if (!keep[k]) continue;
            d.position[kept] = d.position[k];
            d.velocity[kept] = d.velocity[k];
            d.type[kept] = d.type[k];
            d.lifetime[kept] = d.lifetime[k];
            d.id[kept] = d.id[k];
            ++kept;
        }
        for (auto* a : {&d.position, &d.velocity}) a->resize(kept);
        d.type.resize(kept);
        d.lifetime.resize(kept);
        d.id.resize(kept);

        // Emit (eq. 9-10), in fluid-id order.
        emitted[0] = 0;
        for (std::size_t i = 0; i < n; ++i) emitted[i + 1] += emitted[i];
        const std::size_t base = d.size(), added = emitted[n];
        for (auto* a : {&d.position, &d.velocity}) a->resize(base + added);
        d.type.resize(base + added, DiffuseType::foam);
        d.lifetime.resize(base + added);
        d.id.resize(base + added);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                if (emitted[i + 1] == emitted[i]) continue;
                const std::uint64_t id = to.id.empty() ? std::uint64_t(i) : to.id[i];
                Random rng{mix(p.seed ^
                               mix((std::uint64_t(frame) << 40) ^ (std::uint64_t(s) << 32) ^ id)) ^
                           0x5bd1e995ull};
                const double speed = length(v[i]);
                const Vec3 axis = speed > 0.0 ? v[i] * float(1.0 / speed) : Vec3{0, 1, 0};
                // Two unit vectors across the velocity.
                const Vec3 other = std::abs(axis.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
                Vec3 e1 = cross(axis, other);
                e1 = e1 * (1.0f / length(e1));
                const Vec3 e2 = cross(axis, e1);
                for (std::uint32_t k = emitted[i]; k < emitted[i + 1]; ++k) {
                    const float radius = p.particleRadius * std::sqrt(rng.next());
                    const float angle = 2.0f * std::numbers::pi_v<float> * rng.next();
                    const float along = rng.next() * float(speed * dt);
                    const Vec3 radial = std::cos(angle) * e1 + std::sin(angle) * e2;
                    const std::size_t out = base + k;
                    d.position[out] = x[i] + radius * radial + along * axis;
                    // eq. 10, the radial offset taken as a spread of up to
                    // 10 % of the speed (the paper adds the offset itself).
                    d.velocity[out] =
                        v[i] + (0.1f * float(speed) * radius / p.particleRadius) * radial;
                    d.lifetime[out] = p.lifetimeMin + rng.next() * (p.lifetimeMax - p.lifetimeMin);
                    d.id[out] = nextId_ + k;
                }
            }
        });
        nextId_ += added;

        // Classify by fluid neighbours (section 5).
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, d.size()), [&](const auto& range) {
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
                int count = 0;
                cells.forEachNear(d.position[k], [&](std::uint32_t j) {
                    if (length(d.position[k] - x[j]) < h) ++count;
                });
                d.type[k] = count < p.sprayMaxNeighbors    ? DiffuseType::spray
                            : count > p.bubbleMinNeighbors ? DiffuseType::bubble
                                                           : DiffuseType::foam;
            }
        });
    }
    secondsPerSubstep_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() /
        substeps;
}

void writeDiffusePly(const std::filesystem::path& path, const DiffuseParticles& d) {
    static constexpr PlyProperty kProperties[] = {
        {"float", "x"},  {"float", "y"},    {"float", "z"},        {"float", "vx"}, {"float", "vy"},
        {"float", "vz"}, {"uchar", "type"}, {"float", "lifetime"}, {"uint", "id"}};
    writeVertexPly(path, "written by pbf foam", kProperties, d.size(),
                   [&](std::size_t k, char* record) {
                       const float f[6] = {d.position[k].x, d.position[k].y, d.position[k].z,
                                           d.velocity[k].x, d.velocity[k].y, d.velocity[k].z};
                       std::memcpy(record, f, sizeof f);
                       record[24] = static_cast<char>(static_cast<std::uint8_t>(d.type[k]));
                       std::memcpy(record + 25, &d.lifetime[k], 4);
                       const std::uint32_t id = plyId(d.id[k], path);
                       std::memcpy(record + 29, &id, 4);
                   });
}

DiffuseParticles readDiffusePly(const std::filesystem::path& path) {
    const auto fail = [&](const std::string& what) { throw IoError(path.string() + ": " + what); };
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot open");
    // The header writeDiffusePly writes, line by line (comments skipped).
    const std::vector<std::string> expected = {"ply",
                                               "format binary_little_endian 1.0",
                                               "element vertex",
                                               "property float x",
                                               "property float y",
                                               "property float z",
                                               "property float vx",
                                               "property float vy",
                                               "property float vz",
                                               "property uchar type",
                                               "property float lifetime",
                                               "property uint id",
                                               "end_header"};
    std::size_t count = 0;
    std::string line;
    for (std::size_t k = 0; k < expected.size();) {
        if (!std::getline(in, line)) fail("truncated PLY header");
        if (line.starts_with("comment")) continue;
        if (expected[k] == "element vertex") {
            const std::string prefix = "element vertex ";
            if (!line.starts_with(prefix))
                fail("not a diffuse PLY of pbf foam (expected '" + expected[k] + "')");
            count = std::stoul(line.substr(prefix.size()));
        } else if (line != expected[k]) {
            fail("not a diffuse PLY of pbf foam (expected '" + expected[k] + "', got '" + line +
                 "')");
        }
        ++k;
    }
    constexpr std::size_t kRecord = 6 * 4 + 1 + 4 + 4;
    const auto headerEnd = in.tellg();
    in.seekg(0, std::ios::end);
    const auto bytes = static_cast<std::size_t>(in.tellg() - headerEnd);
    in.seekg(headerEnd);
    if (count > bytes / kRecord) fail("file is shorter than its vertex count says");
    DiffuseParticles d;
    d.position.resize(count);
    d.velocity.resize(count);
    d.type.resize(count);
    d.lifetime.resize(count);
    d.id.resize(count);
    std::vector<char> record(kRecord);
    for (std::size_t k = 0; k < count; ++k) {
        if (!in.read(record.data(), std::streamsize(kRecord))) fail("truncated vertex data");
        float f[6];
        std::memcpy(f, record.data(), sizeof f);
        d.position[k] = {f[0], f[1], f[2]};
        d.velocity[k] = {f[3], f[4], f[5]};
        const auto type = static_cast<std::uint8_t>(record[24]);
        if (type > 2)
            fail("diffuse particle " + std::to_string(k) + " has unknown type " +
                 std::to_string(type));
        d.type[k] = DiffuseType(type);
        std::memcpy(&d.lifetime[k], record.data() + 25, 4);
        std::uint32_t id;
        std::memcpy(&id, record.data() + 29, 4);
        d.id[k] = id;
    }
    return d;
}

void writeDiffuseVdb(const std::filesystem::path& path, const DiffuseParticles& d) {
    ParticleFrame frame;
    frame.position = d.position;
    frame.velocity = d.velocity;
    frame.id = d.id;
    detail::ExtraPointAttributes extra;
    std::vector<std::int32_t> types;
    for (const DiffuseType t : d.type) types.push_back(std::int32_t(t));
    extra.ints.emplace_back("type", std::move(types));
    extra.floats.emplace_back("lifetime", d.lifetime);
    detail::writePointsVdb(path, frame, "diffuse", extra);
}

}  // namespace pbf::surface
