// The viewer's simulation thread: it publishes snapshots, pauses where told,
// steps, resets and takes live parameters, while the caller never waits on a step.
#include "sim_worker.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <thread>
#include <vector>

#include "pbf/backend/backend.hpp"
#include "pbf/io/scene.hpp"
#include "support/test_util.hpp"

namespace pbf::render {
namespace {

using namespace std::chrono_literals;

// Polls `condition` for up to 60 s (the machine may be busy).
template <class Condition>
bool waitFor(Condition condition) {
    const auto end = std::chrono::steady_clock::now() + 60s;
    while (std::chrono::steady_clock::now() < end) {
        if (condition()) return true;
        std::this_thread::sleep_for(5ms);
    }
    return false;
}

TEST(SimulationWorker, PausesAtAFrameStepsAndResets) {
    const Scene scene = parseScene(test::smallSceneJson(), "small");
    SimulationWorker worker(scene, false);
    Snapshot snapshot;
    ASSERT_TRUE(waitFor([&] { return worker.takeSnapshot(snapshot); }));
    EXPECT_EQ(snapshot.report.frame, 0);
    EXPECT_EQ(snapshot.speed.size(), countParticles(scene));
    EXPECT_EQ(snapshot.xyz.size(), 3 * countParticles(scene));

    worker.pauseAt(2);
    ASSERT_TRUE(waitFor([&] { return !worker.playing() && worker.framesSimulated() == 2; }));
    std::this_thread::sleep_for(50ms);
    EXPECT_EQ(worker.framesSimulated(), 2) << "kept playing after pauseAt";
    ASSERT_TRUE(
        waitFor([&] { return worker.takeSnapshot(snapshot) || snapshot.report.frame == 2; }));
    EXPECT_EQ(snapshot.report.frame, 2);
    EXPECT_GT(snapshot.report.substeps, 0);
    EXPECT_GT(snapshot.report.stageMs.total, 0.0);

    worker.requestStep();
    ASSERT_TRUE(waitFor([&] { return worker.framesSimulated() == 3; }));
    worker.requestReset();
    ASSERT_TRUE(
        waitFor([&] { return worker.takeSnapshot(snapshot) && snapshot.report.frame == 0; }));
    EXPECT_EQ(worker.framesSimulated(), 0);
}

TEST(SimulationWorker, ReportsRefusedParameters) {
    const Scene scene = parseScene(test::smallSceneJson(), "small");
    SimulationWorker worker(scene, false);
    SimulationParams bad = scene.simulation;
    bad.fluid.viscosity = -1.0f;
    worker.setParams(bad);
    ASSERT_TRUE(waitFor([&] { return !worker.lastError().empty(); }));
    EXPECT_NE(worker.lastError().find("viscosity"), std::string::npos) << worker.lastError();
    SimulationParams good = scene.simulation;
    good.solver.iterations = 7;
    worker.setParams(good);
    ASSERT_TRUE(waitFor([&] { return worker.lastError().empty(); }));
    worker.requestStep();
    Snapshot snapshot;
    ASSERT_TRUE(
        waitFor([&] { return worker.takeSnapshot(snapshot) && snapshot.report.frame == 1; }));
    EXPECT_EQ(snapshot.report.iterations, 7);
}

// A settings change that makes the state guard fire (gravity 100 g against
// a 2 m/s limit): the worker reports the failed frame, pauses, refuses to
// step on until a reset, and shuts down cleanly (before, the exception left
// the thread and ended the program in std::terminate).
TEST(SimulationWorker, StateGuardFailureAfterASettingsChangeIsReported) {
    const Scene scene = parseScene(test::smallSceneJson(R"("guard": {"max_speed": 2})"), "small");
    SimulationWorker worker(scene, false);
    SimulationParams heavy = scene.simulation;
    heavy.gravity = {0.0f, -981.0f, 0.0f};
    worker.setParams(heavy);
    worker.setPlaying(true);
    ASSERT_TRUE(waitFor([&] { return worker.failed(); }));
    EXPECT_FALSE(worker.playing());
    EXPECT_NE(worker.lastError().find("bad state in frame 1"), std::string::npos)
        << worker.lastError();
    EXPECT_NE(worker.lastError().find("exceeds the limit of 2 m/s"), std::string::npos)
        << worker.lastError();
    const int frames = worker.framesSimulated();
    worker.requestStep();
    worker.setPlaying(true);
    std::this_thread::sleep_for(100ms);
    EXPECT_EQ(worker.framesSimulated(), frames) << "stepped on after a failed frame";
    // A reset (with the gravity put back) runs again.
    worker.setParams(scene.simulation);
    worker.requestReset();
    ASSERT_TRUE(waitFor([&] { return !worker.failed(); }));
    worker.requestStep();
    ASSERT_TRUE(waitFor([&] { return worker.framesSimulated() == 1; }));
    EXPECT_TRUE(worker.lastError().empty()) << worker.lastError();
}

// The viewer on the GPU backend (`pbf view --device cuda`; here its CPU
// build, or the device PBF_TEST_DEVICE names): the worker's frames are the
// device's frames, bit for bit, computed by that device's backend. Catches a
// worker that drops its device and steps on the default cpu backend (the
// snapshot names the backend that computed it, whether or not its bits
// differ from the device's), and a publication that mixes up the device's
// particle order.
TEST(SimulationWorker, StepsOnTheDeviceItWasGiven) {
    const char* name = std::getenv("PBF_TEST_DEVICE");
    const BackendKind device = name && *name ? parseBackendKind(name) : BackendKind::CudaOnCpu;
    const DeviceInfo info = deviceInfo(device);
    if (!info.usable) GTEST_SKIP() << "device " << backendName(device) << ": " << info.description;
    const Scene scene = parseScene(test::smallSceneJson(), "small");
    SimulationWorker worker(scene, false, device);
    worker.pauseAt(2);
    ASSERT_TRUE(waitFor([&] { return !worker.playing() && worker.framesSimulated() == 2; }));
    Snapshot snapshot;
    ASSERT_TRUE(waitFor([&] {
        worker.takeSnapshot(snapshot);
        return snapshot.report.frame == 2;
    }));

    const auto framesOn = [&](BackendKind kind) {
        World world(scene, WorldOptions{kind, {}});
        for (int frame = 0; frame < 2; ++frame) EXPECT_TRUE(world.stepFrame().ok());
        const ParticleStore& p = world.particles();
        std::vector<float> xyz;
        for (std::size_t i = 0; i < p.size(); ++i)
            xyz.insert(xyz.end(), {p.position.x[i], p.position.y[i], p.position.z[i]});
        return xyz;
    };
    EXPECT_EQ(snapshot.device, device) << "stepped on " << backendName(snapshot.device);
    EXPECT_EQ(snapshot.xyz, framesOn(device));
}

}  // namespace
}  // namespace pbf::render
