// Necks that let go (equations.hpp, "Strands"). A thread of water in zero
// gravity, 8 particles across, seeded with a 25 % perturbation of the
// cross-section at Rayleigh's fastest wavenumber kR = 0.697, between two
// walls that meet it at about 90 degrees (wall adhesion 0.5, no friction:
// near-symmetry planes, so that no free end retracts through the bulges).
// Its necks thin until they are two particles across; then, with the strand
// rule, they break, and the drops stay apart (at 6 across the necks stalled
// thicker and not all of them broke). Without it
// the necks became force-free strands that held the thread in one piece
// for good (the largest piece was the whole thread). And a short thread
// (half-length 2 R, under the 3 R where a thread can break) recoils into
// one drop.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "pbf/world/world.hpp"
#include "support/test_util.hpp"
#include "validate/drops.hpp"

namespace pbf::test {
namespace {

namespace drops = validation::detail;

constexpr float kRadius = 0.00025f;  // particle radius: 0.5 mm spacing
constexpr float kSpacing = 2.0f * kRadius;

// The fraction of the particles in the largest piece (linked closer than
// one kernel radius).
double largestShare(const World& world) {
    const std::vector<Vec3> x = drops::positions(world);
    return double(drops::largestCluster(x, 2.0f * kSpacing).size()) / double(x.size());
}

TEST(PinchOff, ASeededThreadBreaksIntoDropsThatStayApart) {
    const float R = 4.0f * kSpacing;  // 8 across
    const float kR = 0.697f, seed = 0.25f;
    const float wavelength = 2.0f * std::numbers::pi_v<float> * R / kR;
    const float length = 3.0f * wavelength;
    WorldDef def = drops::waterWorld(kRadius, 1.0f);
    def.simulation.domain = {{0.0f, -3.0f * R, -3.0f * R}, {length, 3.0f * R, 3.0f * R}};
    def.simulation.solver.wallAdhesion = 0.5f;
    def.simulation.solver.friction = 0.0f;
    def.fps = 200.0f;
    const float mean = 1.0f / std::sqrt(1.0f + 0.5f * seed * seed);  // the volume of radius R
    const std::vector<Vec3> sites = drops::latticeSites(
        def, def.simulation.domain, {0.5f * kSpacing, 0.0f, 0.0f}, [&](const Vec3& p) {
            const float r =
                R * mean *
                (1.0f + seed * std::cos(2.0f * std::numbers::pi_v<float> * p.x / wavelength));
            return p.y * p.y + p.z * p.z < r * r;
        });
    World world = drops::worldOf(def, sites);
    // The linear growth rate (Rayleigh 1892): omega = 0.343 sqrt(sigma / (rho R^3))
    // = 33 / s; from rest the seed grows as cosh(omega t) and reaches the
    // radius at acosh(4) / omega = 0.063 s. The first neck breaks near that
    // (0.068 s). The last one's time moves with the rounding: 0.08-0.12 s in
    // release builds, and under the sanitizers' -O2 one neck of three still
    // held at 0.16 s (docs/surface_tension.md, Limits), so it is not asked for.
    while (world.time() < 0.08) stepFrame(world);
    const double first = largestShare(world);
    while (world.time() < 0.16) stepFrame(world);
    const double later = largestShare(world);
    const std::size_t pieces = drops::clusterCount(drops::positions(world), 2.0f * kSpacing);
    std::printf("  %zu particles: largest piece %.2f of them at 0.08 s, %.2f at 0.16 s, %zu pieces\n",
                world.particleCount(), first, later, pieces);
    // A neck broke by 0.08 s (the largest piece holds at most two thirds of
    // the water; before the strand rule it held all of it), and the drops
    // stayed apart: the largest piece has not grown since.
    EXPECT_LT(first, 0.9);
    EXPECT_LE(later, first + 0.02);
    // Drops, not spray.
    EXPECT_LT(pieces, world.particleCount() / 50);
}

TEST(PinchOff, AShortThreadRecoilsIntoOneDrop) {
    const float R = 3.0f * kSpacing;
    WorldDef def = drops::waterWorld(kRadius, 0.03f);
    def.fps = 100.0f;
    const std::vector<Vec3> sites = drops::latticeSites(
        def, def.simulation.domain, {},
        [&](const Vec3& p) { return std::fabs(p.x) < 2.0f * R && p.y * p.y + p.z * p.z < R * R; });
    World world = drops::worldOf(def, sites);
    while (world.time() < 0.06) stepFrame(world);
    const double share = largestShare(world);
    std::printf("  %zu particles: largest piece %.3f of them at 0.06 s\n", world.particleCount(),
                share);
    EXPECT_GT(share, 0.99);
}

}  // namespace
}  // namespace pbf::test
