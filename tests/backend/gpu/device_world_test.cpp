// The GPU backend through pbf::World on the device under test
// (device_test_util.hpp: cuda-on-cpu, or an NVIDIA GPU with
// PBF_TEST_DEVICE=cuda): whole runs against the CPU backend within the
// CPU run's own one-ulp sensitivity (tests/support/drift_check.hpp), with
// solids (analytic and a mesh), emitters, a rigid body and the accuracy
// options; determinism; checkpoints across devices; the reductions; bad
// input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend/gpu/device_test_util.hpp"
#include "core/particle_checks.hpp"
#include "pbf/backend/statistics.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/state_guard.hpp"
#include "pbf/core/threading.hpp"
#include "pbf/io/checkpoint.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/drift_check.hpp"
#include "support/test_util.hpp"

namespace pbf::test {
namespace {

Scene smallDamBreak(const std::string& solverExtra = "") {
    return parseScene(smallDamBreakJson(solverExtra), "small_dam_break");
}

// The small dam break with a 6 cm box of 500 kg/m^3 dropped into the column.
Scene withBody(Scene scene) {
    RigidBodyDescription box;
    box.shape.kind = SolidDescription::Kind::Box;
    box.shape.box = {{0.09f, 0.34f, 0.03f}, {0.15f, 0.4f, 0.09f}};
    box.density = 500.0f;
    box.velocity = {0.0f, -1.0f, 0.0f};
    scene.rigidBodies.push_back(box);
    return scene;
}

WorldOptions onDevice() {
    return WorldOptions{deviceUnderTest(), {}};
}

// Bitwise equality of two particle states (every field, memory order).
void expectSameBits(const ParticleStore& a, const ParticleStore& b, const char* what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    const auto same = [&](const std::vector<float>& x, const std::vector<float>& y,
                          const char* field) {
        ASSERT_EQ(x.size(), y.size()) << what << ": " << field;
        // An optional field that is off is empty: memcmp's pointers may be
        // null then, which it must not be given (UBSan's nonnull check).
        if (x.empty()) return;
        EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(float)), 0)
            << what << ": " << field << " differs";
    };
    same(a.position.x, b.position.x, "x");
    same(a.position.y, b.position.y, "y");
    same(a.position.z, b.position.z, "z");
    same(a.velocity.x, b.velocity.x, "vx");
    same(a.velocity.y, b.velocity.y, "vy");
    same(a.velocity.z, b.velocity.z, "vz");
    same(a.density, b.density, "density");
    same(a.solveAcceleration.x, b.solveAcceleration.x, "warm start's acceleration");
    EXPECT_EQ(a.id, b.id) << what << ": ids (memory order)";
    EXPECT_EQ(a.nextId(), b.nextId()) << what;
}

// ---- Whole runs against the CPU backend -------------------------------------

TEST(DeviceWorld, DamBreakAgreesWithTheCpuOverFiftySubsteps) {
    PBF_REQUIRE_DEVICE();
    DriftOptions options;
    options.afterFrame = [](int frame, const World& cpu, const FrameResult&, const World& device,
                            const FrameResult& deviceFrame) {
        EXPECT_EQ(deviceFrame.report.iterations, 4);  // counted by the device's loop
        if (frame < 50) return;
        // A real flow: the front reached the obstacle.
        EXPECT_GT(cpu.report().state.maxSpeed, 1.0);
        const ParticleStore& p = device.particles();
        EXPECT_GT(*std::max_element(p.position.x.begin(), p.position.x.end()), 0.29f);
        EXPECT_EQ(device.report().state.escaped, 0u);
        EXPECT_EQ(device.report().state.insideSolid, 0u);
    };
    expectDriftWithinOneUlpSensitivity(smallDamBreak(), BackendKind::Cpu, deviceUnderTest(),
                                       options);
}

// 40 substeps: the over-relaxed flow's one-ulp twins reach 0.06-0.07
// spacings by substep 50, where a backend's drift says no more than chaos
// does (tests/backend/reference/world_vs_reference_test.cpp).
TEST(DeviceWorld, OverRelaxedDamBreakAgreesWithTheCpu) {
    PBF_REQUIRE_DEVICE();
    DriftOptions options;
    options.substeps = 40;
    expectDriftWithinOneUlpSensitivity(smallDamBreak(R"(, "over_relaxation": 1.2)"),
                                       BackendKind::Cpu, deviceUnderTest(), options);
}

TEST(DeviceWorld, ConsistentCorrectionDamBreakAgreesWithTheCpu) {
    PBF_REQUIRE_DEVICE();
    expectDriftWithinOneUlpSensitivity(smallDamBreak(R"(, "consistent_correction": 0.45)"),
                                       BackendKind::Cpu, deviceUnderTest(), DriftOptions{});
}

// A rigid body: the device records the coupled surface's moves and sums
// them per body (fixed blocks, block order); the body it moves may drift
// from the CPU run's no faster than that run's one-ulp twin.
TEST(DeviceWorld, RigidBodyAgreesWithTheCpuOverFiftySubsteps) {
    PBF_REQUIRE_DEVICE();
    DriftOptions options;
    options.visible = 1.0;
    options.distance = [](const World& a, const World& b) {
        return double(length(a.bodyStates()[0].position - b.bodyStates()[0].position));
    };
    double largestForce = 0.0;
    options.afterFrame = [&](int frame, const World&, const FrameResult&, const World& device,
                             const FrameResult&) {
        largestForce = std::max(largestForce, double(length(device.bodyLoads()[0].force)));
        if (frame < 50) return;
        // The water pushed the body (slower than free fall), with forces of its weight's size.
        EXPECT_GT(device.bodyStates()[0].velocity.y, -1.0 - 9.81 * 50.0 / 300.0 + 0.2);
        EXPECT_GT(largestForce, 1.0);  // N; the box weighs 1.06 N
        EXPECT_EQ(device.report().state.insideSolid, 0u);
    };
    expectDriftWithinOneUlpSensitivity(withBody(smallDamBreak()), BackendKind::Cpu,
                                       deviceUnderTest(), options);
}

// Emitters append particles on the device every substep (ids continue).
TEST(DeviceWorld, EmitterAgreesWithTheCpu) {
    PBF_REQUIRE_DEVICE();
    Scene scene = smallDamBreak();
    EmitterDescription e;
    e.position = {0.45f, 0.4f, 0.1f};
    e.direction = {0.0f, -1.0f, 0.0f};
    e.radius = 0.03f;
    e.speed = 1.5f;
    scene.emitters.push_back(e);
    DriftOptions options;
    options.substeps = 40;
    options.afterFrame = [](int, const World& cpu, const FrameResult&, const World& device,
                            const FrameResult&) {
        ASSERT_EQ(device.particleCount(), cpu.particleCount());
    };
    expectDriftWithinOneUlpSensitivity(scene, BackendKind::Cpu, deviceUnderTest(), options);
    World device(scene, onDevice());
    const std::size_t before = device.particleCount();
    for (int k = 0; k < 30; ++k) stepFrame(device);
    const ParticleStore& p = device.particles();
    EXPECT_GT(p.size(), before + 30);
    std::vector<std::uint64_t> ids = p.id;
    std::sort(ids.begin(), ids.end());
    for (std::size_t k = 0; k < ids.size(); ++k) ASSERT_EQ(ids[k], k);
}

// A mesh solid (an OpenVDB level set on the host) is its voxels on the
// device (Solid::shapeData), interpolated the same way.
TEST(DeviceWorld, MeshSolidAgreesWithTheCpu) {
    PBF_REQUIRE_DEVICE();
    Scene scene = smallDamBreak();
    SolidDescription& s = scene.solids[0];
    s.kind = SolidDescription::Kind::Mesh;
    s.file = std::string(PBF_TESTS_DATA_DIR) + "/cube.obj";
    s.transform.scale = {0.04f, 0.05f, 0.1f};
    s.transform.translation = {0.32f, 0.025f, 0.1f};
    DriftOptions options;
    options.substeps = 40;
    expectDriftWithinOneUlpSensitivity(scene, BackendKind::Cpu, deviceUnderTest(), options);
}

// ---- The accuracy options ------------------------------------------------------

// Tolerance mode: the device's loop stops when the average compression of
// its density pass (summed in fixed point on the device) is within the
// tolerance, so every frame ends within it; with the warm start and
// over-relaxation it needs fewer iterations than plain Jacobi (omega 1 set
// explicitly: a tolerance alone over-relaxes by default), as on the CPU.
TEST(DeviceWorld, ToleranceModeWithWarmStartAndOverRelaxation) {
    PBF_REQUIRE_DEVICE();
    const std::string tolerance =
        R"(, "max_density_error": 0.002, "min_iterations": 1, "max_iterations": 100)";
    const auto run = [&](const std::string& extra, BackendKind kind) {
        World world(smallDamBreak(tolerance + extra), WorldOptions{kind, {}});
        double iterations = 0.0, most = 0.0;
        for (int frame = 1; frame <= 40; ++frame) {
            const FrameReport f = stepFrame(world);
            EXPECT_LE(f.state.averageDensityError, 0.002) << "frame " << frame;
            EXPECT_LT(f.iterations, 100.0) << "frame " << frame << " hit the iteration cap";
            iterations += f.iterations / 40.0;
            most = std::max(most, f.iterations);
        }
        std::printf("  %-12s %-40s %.2f iterations per substep (most %.0f)\n",
                    std::string(backendName(kind)).c_str(), extra.c_str(), iterations, most);
        return iterations;
    };
    const std::string accelerated = R"(, "warm_start": 0.8, "over_relaxation": 1.2)";
    const double plain = run(R"(, "over_relaxation": 1.0)", deviceUnderTest());
    const double fast = run(accelerated, deviceUnderTest());
    const double cpuFast = run(accelerated, BackendKind::Cpu);
    EXPECT_LT(fast, 0.9 * plain);
    // The same maths: the same work within rounding's flips of the stopping test.
    EXPECT_NEAR(fast, cpuFast, 0.1 * cpuFast);
}

// ---- Determinism -------------------------------------------------------------------

// Everything at once (solids, a body, vorticity, XSPH, tolerance, warm
// start, over-relaxation): the same bits with 1 and 2 OpenMP threads (on a
// GPU: run to run). Catches any order-dependent sum: a float reduction in
// the tolerance test, the statistics or the bodies' reactions, an unstable
// sort.
TEST(DeviceWorld, OneAndTwoThreadsGiveTheSameBits) {
    PBF_REQUIRE_DEVICE();
    const Scene scene = withBody(smallDamBreak(
        R"(, "max_density_error": 0.002, "max_iterations": 20, "warm_start": 0.8, "over_relaxation": 1.2)"));
    const auto run = [&](int threads) {
        setThreadCount(threads);
        World world(scene, onDevice());
        std::vector<FrameReport> reports;
        for (int frame = 0; frame < 30; ++frame) reports.push_back(stepFrame(world));
        setThreadCount(hardwareThreadCount());
        return std::make_pair(world.captureState(), reports);
    };
    const auto [one, oneReports] = run(1);
    const auto [two, twoReports] = run(2);
    expectSameBits(one.particles, two.particles, "1 vs 2 threads");
    ASSERT_EQ(one.bodies.size(), 1u);
    EXPECT_EQ(std::memcmp(&one.bodies[0].position, &two.bodies[0].position, sizeof(Vec3)), 0);
    EXPECT_EQ(std::memcmp(&one.bodies[0].velocity, &two.bodies[0].velocity, sizeof(Vec3)), 0);
    for (std::size_t k = 0; k < oneReports.size(); ++k) {
        EXPECT_EQ(oneReports[k].iterations, twoReports[k].iterations) << "frame " << k + 1;
        EXPECT_EQ(oneReports[k].state.kineticEnergy, twoReports[k].state.kineticEnergy);
    }
}

// ---- Surface tension and the physical viscosity ------------------------------------

// A 8 mm cube of water (512 particles) at zero g resting on the floor of
// its box, beside a sphere and a light box body (a rigid body), with
// water's sigma and adhesion to the walls, the sphere and the body, and
// adaptive substeps (the capillary time step limits them). Only surface
// tension moves anything: the cube rounds off, wets the floor and the
// sphere, and pulls the body towards it (the adhesion's reaction on the
// body). `extra` adds fields to "fluid". 4100 frames per second: one
// capillary substep (0.25 ms) per frame.
Scene surfaceTensionDrop(const std::string& extra = "") {
    return parseScene(R"({
      "name": "surface_tension_drop",
      "domain": {"min": [-0.012, -0.004, -0.008], "max": [0.016, 0.012, 0.008]},
      "gravity": [0, 0, 0],
      "particle_radius": 0.0005,
      "fluid": {"surface_tension": 0.0728)" +
                          extra + R"(},
      "fluid_blocks": [{"min": [-0.004, -0.004, -0.004], "max": [0.004, 0.004, 0.004]}],
      "solids": [{"type": "sphere", "center": [0.008, 0.0, 0.0], "radius": 0.003,
                  "adhesion": 0.7}],
      "rigid_bodies": [{"type": "box", "min": [-0.009, -0.003, -0.003],
                        "max": [-0.005, 0.003, 0.003], "density": 300, "adhesion": 0.8}],
      "solver": {"iterations": 4, "time_step": "adaptive", "wall_adhesion": 0.6},
      "output": {"fps": 4100}
    })",
                      "surface_tension_drop");
}

// The drift check's distance with a body: the particles' and the body's.
double particlesAndBody(const World& a, const World& b) {
    return std::max(maxPositionDifference(a, b),
                    double(length(a.bodyStates()[0].position - b.bodyStates()[0].position)));
}

// Surface tension (cohesion, the walls', a solid's and a body's adhesion,
// the body's reaction) on the device against the CPU within the CPU run's
// own one-ulp sensitivity, with the same substeps. Catches a device stage
// that is missing or computes another acceleration (the cube's particles
// move by ~1e-2 spacings per substep from surface tension alone: a wrong
// term is far outside the drift), a solid's or body's adhesion not
// uploaded, the body's reaction not recorded (the body's drift), and a
// substep count that differs from the CPU's (the capillary limit).
//
// The flow is far more sensitive than the dam break: the cohesion pulls only
// beyond one spacing and flags surface particles by a density threshold,
// and the cube starts on the lattice (pairs exactly one spacing apart), so
// the one-ulp twin jumps from 1e-6 to 0.02 spacings at the second substep
// and reaches ~0.8 by the twentieth. The test therefore holds the device
// to the twin's drift (times 4, as always) and allows 1 spacing in all; a
// wrong term shows at the first substep, where the twin is at 1e-6.
TEST(DeviceWorld, SurfaceTensionAndAdhesionAgreeWithTheCpu) {
    PBF_REQUIRE_DEVICE();
    DriftOptions options;
    options.substeps = 15;
    options.visible = 1.0;
    options.distance = particlesAndBody;
    const Scene scene = surfaceTensionDrop();
    const double capillary = SolverConstants::from(scene.simulation).capillaryTimeStep;
    options.afterFrame = [&](int frame, const World& cpu, const FrameResult& cpuFrame,
                             const World& device, const FrameResult& deviceFrame) {
        EXPECT_EQ(deviceFrame.report.substeps, cpuFrame.report.substeps) << "frame " << frame;
        // The capillary time step sets them (the flow is slow: CFL allows more).
        EXPECT_EQ(cpuFrame.report.substeps, int(std::ceil((1.0 / 4100.0) / capillary - 1e-6)))
            << "frame " << frame;
        if (frame < 15) return;
        // Surface tension moved the water, and the adhesion's reaction the
        // body towards it (+x), on both.
        EXPECT_GT(device.report().state.maxSpeed, 1e-3);
        EXPECT_GT(device.bodyStates()[0].velocity.x, 0.0f);
        EXPECT_GT(cpu.bodyStates()[0].velocity.x, 0.0f);
        EXPECT_EQ(device.report().state.escaped, 0u);
    };
    expectDriftWithinOneUlpSensitivity(scene, BackendKind::Cpu, deviceUnderTest(), options);
}

// The physical viscosity after XSPH (the small dam break: XSPH and
// vorticity on, fixed substeps): the stage reads the velocities before
// XSPH (post_ after XSPH's swap on the device).
TEST(DeviceWorld, PhysicalViscosityAfterXsphAgreesWithTheCpu) {
    PBF_REQUIRE_DEVICE();
    Scene scene = smallDamBreak();
    scene.simulation.fluid.kinematicViscosity = 1e-3f;
    DriftOptions options;
    options.substeps = 30;
    expectDriftWithinOneUlpSensitivity(scene, BackendKind::Cpu, deviceUnderTest(), options);
}

// The physical viscosity without XSPH (fluid.viscosity 0: the device copies
// v for the stage's Jacobi read) with surface tension, and adaptive
// substeps limited by the viscosity's diffusion step (nu dt / dx^2 <=
// 0.05): the device takes the CPU's substeps.
TEST(DeviceWorld, PhysicalViscosityWithSurfaceTensionAgreesWithTheCpu) {
    PBF_REQUIRE_DEVICE();
    const Scene scene = surfaceTensionDrop(R"(, "viscosity": 0, "kinematic_viscosity": 5e-4)");
    const double spacing = scene.simulation.particleSpacing();
    const double diffusion = 0.05 * spacing * spacing / 5e-4;
    ASSERT_LT(diffusion, SolverConstants::from(scene.simulation).capillaryTimeStep);
    DriftOptions options;
    options.substeps = 20;
    options.distance = particlesAndBody;
    options.afterFrame = [&](int frame, const World&, const FrameResult& cpuFrame, const World&,
                             const FrameResult& deviceFrame) {
        EXPECT_EQ(deviceFrame.report.substeps, cpuFrame.report.substeps) << "frame " << frame;
        EXPECT_EQ(cpuFrame.report.substeps, int(std::ceil((1.0 / 4100.0) / diffusion - 1e-6)))
            << "frame " << frame;
    };
    expectDriftWithinOneUlpSensitivity(scene, BackendKind::Cpu, deviceUnderTest(), options);
}

// Surface tension, adhesion (walls, solid, body) and the physical viscosity
// on: the same bits with 1 and 2 OpenMP threads (on a GPU: run to run).
// Catches an order-dependent sum in the new stages or in the body's
// reaction from the adhesion.
TEST(DeviceWorld, SurfaceTensionGivesTheSameBitsOnOneAndTwoThreads) {
    PBF_REQUIRE_DEVICE();
    const Scene scene = surfaceTensionDrop(R"(, "kinematic_viscosity": 1e-5)");
    const auto run = [&](int threads) {
        setThreadCount(threads);
        World world(scene, onDevice());
        for (int frame = 0; frame < 40; ++frame) stepFrame(world);
        setThreadCount(hardwareThreadCount());
        return world.captureState();
    };
    const WorldState one = run(1);
    const WorldState two = run(2);
    expectSameBits(one.particles, two.particles, "1 vs 2 threads");
    ASSERT_EQ(one.bodies.size(), 1u);
    EXPECT_EQ(std::memcmp(&one.bodies[0].position, &two.bodies[0].position, sizeof(Vec3)), 0);
    EXPECT_EQ(std::memcmp(&one.bodies[0].velocity, &two.bodies[0].velocity, sizeof(Vec3)), 0);
    EXPECT_NE(one.bodies[0].velocity.x, 0.0f);  // the adhesion's reaction moved the body
}

// ---- Checkpoints ---------------------------------------------------------------------

// A checkpoint is the particles in memory order plus the rest of the
// state; one written by a World on the device and read back into a fresh
// World on the device continues bit-identically (what `pbf run --resume`
// does after a kill).
TEST(DeviceWorld, CheckpointResumesBitIdentically) {
    PBF_REQUIRE_DEVICE();
    const Scene scene = withBody(smallDamBreak(R"(, "warm_start": 0.8)"));
    const std::uint64_t fingerprint = 42;
    World straight(scene, onDevice());
    for (int frame = 0; frame < 12; ++frame) stepFrame(straight);

    World first(scene, onDevice());
    for (int frame = 0; frame < 6; ++frame) stepFrame(first);
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / "pbf_device_checkpoint.pbfc";
    writeCheckpoint(file, captureCheckpoint(first, fingerprint));
    World resumed(scene, onDevice());
    restoreCheckpoint(readCheckpoint(file), resumed, fingerprint, file.string());
    std::filesystem::remove(file);
    for (int frame = 0; frame < 6; ++frame) stepFrame(resumed);
    expectSameBits(straight.captureState().particles, resumed.captureState().particles,
                   "straight vs resumed");
    EXPECT_EQ(resumed.frame(), 12);
}

// Written on the device, resumed on the CPU backend: a valid run (no
// particle escapes or enters a solid, nothing explodes) that stays close to
// the device's own continuation.
TEST(DeviceWorld, CheckpointWrittenOnTheDeviceResumesOnTheCpu) {
    PBF_REQUIRE_DEVICE();
    const Scene scene = smallDamBreak();
    const std::uint64_t fingerprint = 7;
    World device(scene, onDevice());
    for (int frame = 0; frame < 20; ++frame) stepFrame(device);
    const Checkpoint checkpoint = captureCheckpoint(device, fingerprint);
    World cpu(scene, WorldOptions{BackendKind::Cpu, {}});
    restoreCheckpoint(checkpoint, cpu, fingerprint, "checkpoint");
    ASSERT_EQ(cpu.particleCount(), device.particleCount());
    for (int frame = 0; frame < 10; ++frame) {
        const FrameReport cpuFrame = stepFrame(cpu);
        stepFrame(device);
        EXPECT_EQ(cpuFrame.state.escaped, 0u);
        EXPECT_EQ(cpuFrame.state.insideSolid, 0u);
    }
    EXPECT_LT(maxPositionDifference(cpu, device), 0.1 * scene.simulation.particleSpacing());
}

// ---- Reductions -------------------------------------------------------------------------

// The device's statistics, largest speed and state guard are the host's
// functions' values on the downloaded state: the same per-particle terms
// (backend/statistics_partial.hpp, core/particle_checks.hpp) in the same
// blocks, added in block order.
TEST(DeviceWorld, ReductionsEqualTheHostsOnTheSameState) {
    PBF_REQUIRE_DEVICE();
    const Scene scene = smallDamBreak();
    World world(scene, onDevice());
    for (int frame = 0; frame < 30; ++frame) stepFrame(world);
    const ParticleStore state = world.particles();
    const StateStatistics device = world.report().state;
    const StateStatistics host =
        computeStatistics(state, world.constants(), scene.simulation.domain, &world.solids(),
                          scene.simulation.particleRadius);
    EXPECT_EQ(device.averageDensityError, host.averageDensityError);
    EXPECT_EQ(device.maxDensityError, host.maxDensityError);
    EXPECT_EQ(device.kineticEnergy, host.kineticEnergy);
    EXPECT_EQ(device.maxSpeed, host.maxSpeed);
    EXPECT_EQ(device.momentum, host.momentum);
    EXPECT_EQ(device.escaped, host.escaped);
    EXPECT_EQ(world.backend().maxSpeed(), maxSpeed(state));
    EXPECT_GT(device.maxSpeed, 1.0);

    // The guard finds the first bad particle in memory order: two made bad.
    WorldState bad = world.captureState();
    bad.particles.velocity.y[700] = std::nanf("");
    bad.particles.position.x[300] = 1e30f * 1e30f;  // infinity
    world.restoreState(bad);
    const std::optional<BadParticle> found = world.backend().findBadParticle(100.0);
    ASSERT_TRUE(found.has_value());
    EXPECT_EQ(found->index, 300u);
    EXPECT_EQ(found->id, bad.particles.id[300]);
    EXPECT_EQ(found->problem, findBadParticle(bad.particles, 100.0)->problem);
    // And the frame loop reports it naming the particle.
    const FrameResult r = world.stepFrame();
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error->message.find("particle id " + std::to_string(bad.particles.id[300])),
              std::string::npos)
        << r.error->message;
}

// ---- Memory and bad input ----------------------------------------------------------

// The 1M-particle dam break fits in 300 bytes per particle of device memory
// (the backend's table, sparse grid included), and the table is honest: a
// run's allocations stay within it.
TEST(DeviceWorld, TheMillionParticleDamBreakFitsInThreeHundredBytesPerParticle) {
    Scene scene = loadScene(scenePath("dam_break.json"));
    const double base = double(countParticles(scene));
    scene.simulation.particleRadius *= float(std::cbrt(base / 1e6));
    const double particles = double(countParticles(scene));
    const double perParticle = double(deviceBytesPerParticle(scene.simulation, false));
    std::printf("  %.0f particles: %.0f bytes per particle on the device\n", particles,
                perParticle);
    EXPECT_NEAR(particles, 1e6, 2e4);
    EXPECT_LE(perParticle, 300.0);

    PBF_REQUIRE_DEVICE();
    Scene small = scene;
    small.simulation.particleRadius *= 5.0f;  // 8k particles
    small.simulation.fluid.vorticity = 0.1f;
    World world(small, onDevice());
    for (int frame = 0; frame < 2; ++frame) stepFrame(world);
    const double used = double(world.backend().diagnostics().memoryBytes);
    const double n = double(world.particleCount());
    const double table = n * double(deviceBytesPerParticle(small.simulation, false));
    std::printf("  %.0f particles: %.0f bytes per particle used, %.0f in the table\n", n, used / n,
                table / n);
    EXPECT_LE(used, table * 1.02 + 65536.0);  // + the solids and per-block sums
}

// The memory table (the admission check's) counts exactly the arrays a
// running backend holds per particle, with every optional term on: surface
// tension (g, nb, kappa), XSPH and the physical viscosity, vorticity
// confinement, the warm start and a rigid body's reaction records.
TEST(DeviceWorld, TheMemoryTableCountsTheArraysAllocatedWithEveryTermOn) {
    PBF_REQUIRE_DEVICE();
    Scene scene = withBody(smallDamBreak());
    SimulationParams& s = scene.simulation;
    s.fluid.surfaceTension = 0.0728f;
    s.fluid.viscosity = 0.01f;
    s.fluid.kinematicViscosity = 1e-6f;
    s.fluid.vorticity = 0.1f;
    s.solver.warmStart = 0.5f;
    World world(scene, onDevice());
    stepFrame(world);
    const std::size_t n = world.particleCount();
    const std::size_t held = deviceUnderTest() == BackendKind::Cuda
                                 ? gpu::on_gpu::particleArrayBytes(world.backend())
                                 : gpu::on_cpu::particleArrayBytes(world.backend());
    EXPECT_EQ(held, n * gpu::particleArrayBytes(s, true))
        << "the arrays held per particle and device_memory.cpp's table disagree";
    // The settings reach the table: each term's arrays are counted.
    SimulationParams plain = s;
    plain.fluid.surfaceTension = 0.0f;
    EXPECT_EQ(gpu::particleArrayBytes(s, true) - gpu::particleArrayBytes(plain, true),
              8 * sizeof(float));  // s, g, nb, kappa
}

TEST(DeviceWorld, ASceneTooLargeForTheDeviceIsRefusedNamingIt) {
    PBF_REQUIRE_DEVICE();
    WorldOptions options = onDevice();
    options.backendOptions.deviceMemoryBytes = std::size_t{64} << 10;  // 64 KiB free
    try {
        World world(smallDamBreak(), options);
        FAIL() << "a 1080-particle scene fitted in 64 KiB";
    } catch (const SceneError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("small_dam_break: fluid_blocks: 1080 particles need about"),
                  std::string::npos)
            << message;
        EXPECT_NE(message.find("on device " + std::string(backendName(deviceUnderTest()))),
                  std::string::npos)
            << message;
    }
}

TEST(DeviceWorld, UnknownDeviceNamesTheChoices) {
    try {
        parseBackendKind("tpu");
        FAIL() << "tpu parsed";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "device: must be cpu, reference, cuda or cuda-on-cpu, got \"tpu\"");
    }
}

// Without a usable GPU (no GPU here, or a build without CUDA), asking for
// one is a clear error naming the device.
TEST(DeviceWorld, AnUnusableDeviceIsAnErrorNamingIt) {
    const DeviceInfo cuda = deviceInfo(BackendKind::Cuda);
    if (cuda.usable) GTEST_SKIP() << "a GPU is here: " << cuda.description;
    try {
        World world(smallDamBreak(), WorldOptions{BackendKind::Cuda, {}});
        FAIL() << "a World on an unusable device";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "device cuda: " + cuda.description);
    }
}

}  // namespace
}  // namespace pbf::test
