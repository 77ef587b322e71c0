// Two backends running the same flow, compared against the flow's own
// sensitivity (used by world_vs_reference_test.cpp and the GPU backend's
// tests).
//
// Tolerance: two backends compute the same maths with different rounding
// (one step differs by about an ulp of the positions: see
// tests/backend/reference/stage_agreement.hpp), and a splashing flow
// amplifies any such difference: particles at a wall switch between
// "touching" and "not touching" (box clamp, wall response), the
// constraint's clamp C >= 0 and the neighbour lists switch at thresholds.
// No closed-form bound survives that, so the check measures the flow's own
// sensitivity: two more runs of the first backend whose initial positions
// differ by one ulp (in x in one, in z in the other), two realisations of
// the same amplification. The other backend may not drift from the first
// run faster than the faster of the two does (times 4: realisations differ
// by up to ~5x, measured: the rigid body's centre at substep 50 drifts
// 8e-6 spacings in the x twin, 4.4e-5 in the z twin; the larger of two is
// the steadier yardstick), with a floor of a few ulps for the first steps. A wrong term (s_corr dropped, say) moves particles
// by ~1e-3 spacings in the first step, 1000 times the floor, and fails at
// once.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"

namespace pbf::test {

// 1080 particles (12 x 15 x 6) collapsing towards a box obstacle, one fixed
// substep of 1/300 s per frame, XSPH and vorticity confinement on: every
// stage of both backends runs.
inline std::string smallDamBreakJson(const std::string& solverExtra = "") {
    return R"({
      "name": "small_dam_break",
      "domain": {"min": [0, 0, 0], "max": [0.6, 0.5, 0.2]},
      "particle_radius": 0.01,
      "fluid": {"viscosity": 0.01, "vorticity": 0.05},
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.24, 0.3, 0.12]}],
      "solids": [{"type": "box", "min": [0.3, 0, 0.05], "max": [0.34, 0.05, 0.15]}],
      "solver": {"iterations": 4, "time_step": "fixed", "substeps": 1)" +
           solverExtra + R"(},
      "output": {"fps": 300}
    })";
}

// Largest distance between the same particle (by id) in the two worlds.
inline double maxPositionDifference(const World& a, const World& b) {
    const ParticleStore& pa = a.particles();
    const ParticleStore& pb = b.particles();
    std::vector<Vec3> byId(pb.size());
    for (std::size_t k = 0; k < pb.size(); ++k) byId[pb.id[k]] = pb.position.get(k);
    double largest = 0.0;
    for (std::size_t k = 0; k < pa.size(); ++k)
        largest = std::max(largest, double(length(pa.position.get(k) - byId[pa.id[k]])));
    return largest;
}

// Moves every particle of `world` by one ulp along one axis (a one-ulp twin).
inline void perturbByOneUlp(World& world, std::vector<float> Float3Array::*axis) {
    ParticleStore state = world.particles();
    for (float& x : state.position.*axis) x = std::nextafter(x, 1.0f);
    WorldState s = world.captureState();
    s.particles = std::move(state);
    world.restoreState(std::move(s));
}

struct DriftOptions {
    int substeps = 50;     // frames (one substep each in the scenes used)
    double visible = 0.1;  // spacings: the drift must stay far below this
    // Distance between the two worlds, metres (default: the largest
    // particle distance by id; bodies: the body's centre).
    std::function<double(const World&, const World&)> distance = maxPositionDifference;
    // Called after every frame with both worlds and their frames' results
    // (extra checks).
    std::function<void(int frame, const World& base, const FrameResult& baseFrame,
                       const World& tested, const FrameResult& testedFrame)>
        afterFrame;
};

// Runs `scene` on `base`, on two one-ulp-perturbed copies of it (the
// twins) and on `tested` for options.substeps frames, and checks that
// `tested` drifts from `base` no faster than 4 times the faster twin
// (floor: 8 ulps of the largest coordinate). Returns the largest drift of
// `tested`, in spacings.
inline double expectDriftWithinOneUlpSensitivity(const Scene& scene, BackendKind base,
                                                 BackendKind tested,
                                                 const DriftOptions& options = {}) {
    World first(scene, WorldOptions{base, {}});
    World twinX(scene, WorldOptions{base, {}});
    World twinZ(scene, WorldOptions{base, {}});
    World other(scene, WorldOptions{tested, {}});
    EXPECT_EQ(first.particleCount(), other.particleCount());
    perturbByOneUlp(twinX, &Float3Array::x);
    perturbByOneUlp(twinZ, &Float3Array::z);

    const double spacing = scene.simulation.particleSpacing();
    const Vec3 e = scene.simulation.domain.max;
    const double largestCoordinate = std::max({std::fabs(e.x), std::fabs(e.y), std::fabs(e.z)});
    const double floor = 8.0 * 0x1p-24 * largestCoordinate / spacing;
    double drift = 0.0, driftX = 0.0, driftZ = 0.0;  // largest so far, in spacings
    const std::string a(backendName(base)), b(backendName(tested));
    std::printf("  frame  max |x_%s - x_%s|  twins: max |x_%s - x_%s'| (x, z)  (spacings)\n",
                a.c_str(), b.c_str(), a.c_str(), a.c_str());
    for (int frame = 1; frame <= options.substeps; ++frame) {
        FrameResult results[4];
        World* worlds[4] = {&first, &twinX, &twinZ, &other};
        for (int k = 0; k < 4; ++k) {
            results[k] = worlds[k]->stepFrame();
            EXPECT_TRUE(results[k].ok())
                << backendName(worlds[k]->backend().kind()) << ": " << results[k].error->message;
            if (!results[k].ok()) return drift;
        }
        drift = std::max(drift, options.distance(first, other) / spacing);
        driftX = std::max(driftX, options.distance(first, twinX) / spacing);
        driftZ = std::max(driftZ, options.distance(first, twinZ) / spacing);
        const double twinDrift = std::max(driftX, driftZ);
        if (frame <= 2 || frame % 10 == 0)
            std::printf("  %5d  %21.3g  %15.3g %9.3g\n", frame, drift, driftX, driftZ);
        if (options.afterFrame) options.afterFrame(frame, first, results[0], other, results[3]);
        EXPECT_LE(drift, 4.0 * std::max(twinDrift, floor)) << "frame " << frame;
        if (drift > 4.0 * std::max(twinDrift, floor)) return drift;
    }
    EXPECT_LT(drift, options.visible);  // and stayed far below anything visible
    return drift;
}

}  // namespace pbf::test
