// Outlets: water that reaches one leaves the simulation. A dam break drains
// through a plane past its toe, and a small box in the middle of the block
// takes out particles whose ids are in the middle of the id range: every
// backend removes exactly the particles in the outlets, the rest keep their
// ids and their order, the count balances, and everything that reads
// particles by id (the scripting arrays, PLY frames, checkpoints, resuming)
// stays right with the gaps.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "pbf/io/checkpoint.hpp"
#include "pbf/io/io.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/reliability_util.hpp"
#include "support/test_util.hpp"

namespace {

constexpr float kDrainX = 0.3f;  // the plane outlet: x > 0.3 m leaves
const pbf::Aabb kHole{{0.08f, 0.08f, 0.08f}, {0.12f, 0.12f, 0.12f}};  // the box outlet

std::string drainJson(const std::string& extraOutlet = "") {
    return R"({
      "name": "drain",
      "domain": {"min": [0, 0, 0], "max": [0.4, 0.3, 0.2]},
      "particle_radius": 0.01,
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}],
      "outlets": [
        {"type": "plane", "point": [0.3, 0, 0], "normal": [1, 0, 0]},
        {"type": "box", "min": [0.08, 0.08, 0.08], "max": [0.12, 0.12, 0.12]})" +
           extraOutlet + "]}";
}

pbf::Scene drainScene() {
    return pbf::parseScene(drainJson(), "drain.json");
}

bool inAnOutlet(const pbf::Vec3& x) {
    return x.x > kDrainX || kHole.contains(x);
}

std::vector<std::uint64_t> sortedIds(const pbf::ParticleStore& p) {
    std::vector<std::uint64_t> ids = p.id;
    std::sort(ids.begin(), ids.end());
    return ids;
}

class OutletsOn : public ::testing::TestWithParam<pbf::BackendKind> {};

TEST_P(OutletsOn, WaterThatReachesAnOutletLeavesAndTheRestKeepsItsIds) {
    if (!pbf::deviceInfo(GetParam()).usable) GTEST_SKIP() << "backend not usable here";
    pbf::WorldOptions options;
    options.backend = GetParam();
    pbf::World world(drainScene(), options);
    ASSERT_EQ(world.particleCount(), 1000u);  // 10 x 10 x 10
    // The lattice sites in the hole: 2 x 2 x 2, ids in the middle of the range.
    std::set<std::uint64_t> inHole;
    for (std::size_t i = 0; i < world.particles().size(); ++i)
        if (kHole.contains(world.particles().position.get(i)))
            inHole.insert(world.particles().id[i]);
    ASSERT_EQ(inHole.size(), 8u);
    EXPECT_GT(*inHole.begin(), 100u);
    EXPECT_LT(*inHole.rbegin(), 900u);

    std::vector<std::uint64_t> before = sortedIds(world.particles());
    std::uint64_t removed = 0;
    for (int frame = 1; frame <= 20; ++frame) {
        SCOPED_TRACE(frame);
        const pbf::FrameReport r = pbf::test::stepFrame(world);
        const pbf::ParticleStore& p = world.particles();
        // The balance, exactly: the frame's count is the last one's less
        // what the outlets removed.
        EXPECT_EQ(r.emitted, 0u);
        EXPECT_EQ(p.size(), before.size() - r.removed);
        EXPECT_EQ(r.state.particles, p.size());
        removed += r.removed;
        EXPECT_EQ(world.removedParticles(), removed);
        for (std::size_t i = 0; i < p.size(); ++i)
            ASSERT_FALSE(inAnOutlet(p.position.get(i))) << "particle id " << p.id[i];
        // The particles that stay are particles that were there: no id new,
        // none twice.
        const std::vector<std::uint64_t> now = sortedIds(p);
        EXPECT_EQ(std::adjacent_find(now.begin(), now.end()), now.end());
        EXPECT_TRUE(std::includes(before.begin(), before.end(), now.begin(), now.end()));
        if (frame == 1) {
            for (const std::uint64_t id : inHole)
                EXPECT_FALSE(std::binary_search(now.begin(), now.end(), id)) << "id " << id;
        }
        before = now;
    }
    // The front reached the drain (2 sqrt(g h) = 2.8 m/s: 0.1 m in 0.04 s)
    // and a good part of the water left through it.
    EXPECT_GT(removed, 100u);
    EXPECT_LT(removed, 900u);
    EXPECT_EQ(world.particleCount(), 1000u - removed);
}

INSTANTIATE_TEST_SUITE_P(Backends, OutletsOn, pbf::test::everyBackendHere(),
                         pbf::test::backendTestName);

void expectSameState(const pbf::World& a, const pbf::World& b) {
    const pbf::WorldState sa = a.captureState();
    const pbf::WorldState sb = b.captureState();
    ASSERT_EQ(sa.particles.size(), sb.particles.size());
    EXPECT_EQ(sa.particles.id, sb.particles.id);
    EXPECT_EQ(sa.particles.position.x, sb.particles.position.x);
    EXPECT_EQ(sa.particles.position.y, sb.particles.position.y);
    EXPECT_EQ(sa.particles.velocity.z, sb.particles.velocity.z);
    EXPECT_EQ(sa.removed, sb.removed);
}

// Removal keeps the determinism: 1 and 2 threads give the same bits, and a
// state captured mid-outflow (written to a checkpoint file and read back)
// continues bit for bit, with the count of removed particles.
TEST(Outlets, OutflowIsDeterministicAndResumesBitIdentically) {
    const pbf::Scene scene = drainScene();
    pbf::World two(scene);
    std::optional<pbf::World> one;
    {
        const pbf::test::ThreadCountScope oneThread(1);
        one.emplace(scene);
        for (int frame = 0; frame < 12; ++frame) pbf::test::stepFrame(*one);
    }
    for (int frame = 0; frame < 6; ++frame) pbf::test::stepFrame(two);
    ASSERT_GT(two.removedParticles(), 8u);  // the drain is running
    const std::filesystem::path dir = pbf::test::freshTestDirectory("outlets_resume");
    pbf::writeCheckpoint(dir / "c.pbfck", pbf::captureCheckpoint(two, scene.fingerprint));
    pbf::World resumed(scene);
    pbf::restoreCheckpoint(pbf::readCheckpoint(dir / "c.pbfck"), resumed, scene.fingerprint,
                           "c.pbfck");
    EXPECT_EQ(resumed.removedParticles(), two.removedParticles());
    for (int frame = 6; frame < 12; ++frame) {
        pbf::test::stepFrame(two);
        pbf::test::stepFrame(resumed);
    }
    expectSameState(*one, two);
    expectSameState(two, resumed);
}

// After removals the scripting arrays are in id order with gaps: row k is
// the k-th smallest id, and a script's write to a row lands on that
// particle. The PLY frame lists the same ids.
TEST(Outlets, ArraysAndFilesFollowTheIdsThatStay) {
    pbf::World world(drainScene());
    for (int frame = 0; frame < 6; ++frame) pbf::test::stepFrame(world);
    ASSERT_GT(world.removedParticles(), 8u);
    pbf::ParticleArrays& a = world.arraysById();
    ASSERT_EQ(a.count, world.particleCount());
    const std::vector<std::uint64_t> ids = sortedIds(world.particles());
    EXPECT_EQ(*a.id, ids);
    EXPECT_GT(ids.back(), a.count);  // there are gaps
    // Row k shows the particle with id ids[k].
    const pbf::ParticleStore& p = world.particles();
    for (std::size_t i = 0; i < p.size(); i += 37) {
        const auto k = std::size_t(std::lower_bound(ids.begin(), ids.end(), p.id[i]) - ids.begin());
        EXPECT_EQ((*a.position)[3 * k + 1], p.position.y[i]);
    }
    // Lift the particle of the last row above the water and stop it: a
    // frame later it has fallen g t^2 / 2 from there (and no other did).
    const std::uint64_t lifted = ids.back();
    const std::size_t row = a.count - 1;
    const float lift[3] = {0.05f, 0.28f, 0.1f};
    for (int c = 0; c < 3; ++c) {
        (*a.position)[3 * row + c] = lift[c];
        (*a.velocity)[3 * row + c] = 0.0f;
    }
    pbf::test::stepFrame(world);
    const pbf::ParticleStore& after = world.particles();
    const auto at = std::find(after.id.begin(), after.id.end(), lifted);
    ASSERT_NE(at, after.id.end());
    const pbf::Vec3 x = after.position.get(std::size_t(at - after.id.begin()));
    const double t = world.frameDuration();
    EXPECT_NEAR(x.x, 0.05, 1e-4);
    EXPECT_NEAR(x.y, 0.28 - 0.5 * 9.81 * t * t, 1e-3);

    const std::filesystem::path dir = pbf::test::freshTestDirectory("outlets_ply");
    pbf::writeParticlesPly(dir / "f.ply", world.particles());
    const pbf::ParticleFrame frame = pbf::readParticlesPly(dir / "f.ply");
    EXPECT_EQ(frame.id, sortedIds(world.particles()));
    EXPECT_EQ(*world.arraysById().id, frame.id);
}

TEST(Outlets, BadOutletsAreRefusedNamingTheField) {
    const auto error = [](const std::string& outlet) {
        try {
            pbf::parseScene(drainJson(", " + outlet), "drain.json");
        } catch (const pbf::SceneError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    const std::pair<const char*, const char*> refused[] = {
        {R"({"type": "disc"})", "outlets[2].type"},
        {R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]})",
         "outlets[2].normal: must be a non-zero vector"},
        {R"({"type": "plane", "point": [0, 0, 0]})", "outlets[2].normal"},
        {R"({"type": "box", "min": [0, 0, 0], "max": [0.3, 0.25, 0.2]})",
         "outlets[2]: the outlet covers all of fluid_blocks[0]"},
        {R"({"type": "plane", "point": [0, 0.5, 0], "normal": [0, -1, 0]})",
         "outlets[2]: the outlet covers the whole domain"},
        {R"({"type": "plane", "point": [0, 0.5, 0], "normal": [0, 1, 0]})",
         "outlets[2].point: the plane leaves the whole domain outside"},
        {R"({"type": "box", "min": [1, 1, 1], "max": [2, 2, 2]})",
         "outlets[2].min: the outlet must overlap the domain"},
        {R"({"type": "box", "min": [0.1, 0, 0], "max": [0.05, 0.1, 0.1]})",
         "outlets[2].max: must be greater than min"},
    };
    for (const auto& [outlet, message] : refused)
        EXPECT_NE(error(outlet).find(message), std::string::npos)
            << outlet << ": " << error(outlet);
    // A nozzle inside an outlet would pour straight into it.
    const std::string withEmitter = R"({
      "name": "e", "domain": {"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}, "particle_radius": 0.01,
      "emitters": [{"position": [0.35, 0.3, 0.2], "direction": [0, -1, 0], "radius": 0.03,
                    "speed": 1}],
      "outlets": [{"type": "plane", "point": [0.3, 0, 0], "normal": [1, 0, 0]}]})";
    try {
        pbf::parseScene(withEmitter, "e.json");
        ADD_FAILURE() << "accepted";
    } catch (const pbf::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("outlets[0]: the outlet contains the nozzle of "
                                             "emitters[0]"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
