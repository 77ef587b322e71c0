// Solids: distance fields, mesh loading and its errors, collisions that
// never leak, boundary density at solids, particles not spawned in solids.
#include "pbf/geometry/solids.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "backend/boundary.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace {

using pbf::Vec3;

const std::string kData = std::string(PBF_TESTS_DATA_DIR) + "/";

TEST(Solids, AnalyticDistancesAndNormals) {
    Vec3 n;
    auto box = pbf::makeBoxSolid({{0, 0, 0}, {1, 1, 1}});
    EXPECT_FLOAT_EQ(box->signedDistance({2, 0.5f, 0.5f}, n), 1.0f);
    EXPECT_EQ(n, (Vec3{1, 0, 0}));
    EXPECT_FLOAT_EQ(box->signedDistance({0.5f, 0.9f, 0.5f}, n), -0.1f);
    EXPECT_EQ(n, (Vec3{0, 1, 0}));
    EXPECT_NEAR(box->signedDistance({2, 2, 0.5f}, n), std::sqrt(2.0f), 1e-6f);

    auto sphere = pbf::makeSphereSolid({0, 0, 0}, 0.5f);
    EXPECT_FLOAT_EQ(sphere->signedDistance({0, 2, 0}, n), 1.5f);
    EXPECT_EQ(n, (Vec3{0, 1, 0}));
    EXPECT_FLOAT_EQ(sphere->signedDistance({0, 0, 0.25f}, n), -0.25f);

    auto plane = pbf::makePlaneSolid({0, 0.1f, 0}, {0, 2, 0}, {{-1, -1, -1}, {1, 1, 1}});
    EXPECT_FLOAT_EQ(plane->signedDistance({0.3f, 0.5f, 0}, n), 0.4f);
    EXPECT_FLOAT_EQ(plane->signedDistance({0.3f, -0.4f, 0}, n), -0.5f);

    auto cylinder = pbf::makeCylinderSolid({0, 0, 0}, {0, 1, 0}, 0.2f, 1.0f);
    EXPECT_NEAR(cylinder->signedDistance({0.5f, 0.5f, 0}, n), 0.3f, 1e-6f);
    EXPECT_NEAR(n.x, 1.0f, 1e-6f);
    EXPECT_NEAR(cylinder->signedDistance({0, 1.5f, 0}, n), 0.5f, 1e-6f);
    EXPECT_NEAR(cylinder->signedDistance({0, 0.5f, 0.1f}, n), -0.1f, 1e-6f);
    EXPECT_NEAR(cylinder->signedDistance({0.5f, 1.4f, 0}, n), 0.5f,
                1e-6f);  // corner: sqrt(.3^2+.4^2)
}

TEST(Solids, MeshDistanceMatchesTheShape) {
    pbf::MeshInfo info;
    pbf::Transform t;
    t.scale = {0.2f, 0.2f, 0.2f};
    t.translation = {0.1f, 0.1f, 0.1f};
    pbf::MeshSolidOptions options{0.004f, 0.05f, 0.01f};
    auto mesh = pbf::loadMeshSolid(kData + "cube.obj", t, options, &info);
    EXPECT_TRUE(info.closed());
    EXPECT_EQ(info.triangles, 12u);
    auto box = pbf::makeBoxSolid({{0.1f, 0.1f, 0.1f}, {0.3f, 0.3f, 0.3f}});
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(0.07f, 0.33f);
    for (int k = 0; k < 300; ++k) {
        const Vec3 p{u(rng), u(rng), u(rng)};
        Vec3 n1, n2;
        const float exact = box->signedDistance(p, n2);
        if (std::fabs(exact) > 0.04f) continue;  // inside the narrow band only
        EXPECT_NEAR(mesh->signedDistance(p, n1), exact, 0.5f * options.voxelSize)
            << p.x << " " << p.y << " " << p.z;
    }
}

TEST(Solids, StanfordBunnyIsClosed) {
    pbf::MeshInfo info;
    pbf::Transform t;
    t.scale = {0.035f, 0.035f, 0.035f};
    auto bunny = pbf::loadMeshSolid(pbf::test::scenePath("assets/bunny.obj"), t,
                                    {0.004f, 0.05f, 0.008f}, &info);
    EXPECT_TRUE(info.closed());
    EXPECT_EQ(info.triangles, 3674u);
    Vec3 n;
    EXPECT_LT(bunny->signedDistance({0.0f, 0.12f, 0.0f}, n), 0.0f);  // inside the body
    EXPECT_GT(bunny->signedDistance({0.0f, 0.5f, 0.0f}, n), 0.0f);   // above the ears' tips
}

TEST(Solids, BadMeshesGiveClearErrors) {
    const pbf::MeshSolidOptions options{0.01f, 0.05f, 0.01f};
    auto expectError = [&](const std::string& file, const std::string& fragment,
                           double maxVoxels = 2e8) {
        try {
            pbf::loadMeshSolid(file, {}, options, nullptr, maxVoxels);
            FAIL() << "no error for " << file;
        } catch (const pbf::SolidError& e) {
            EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    expectError(kData + "missing.obj", "no such file");
    expectError(kData + "empty.obj", "no triangles");
    expectError(kData + "garbage.obj", "no triangles");
    expectError(kData + "nan_vertex.obj", "not finite");
    expectError(kData + "bad_index.obj", "missing vertex");
    expectError(kData + "cube.stl", "no such file");
    expectError(kData + "../CMakeLists.txt", "unsupported mesh format");
    expectError(kData + "cube.obj", "voxels", 10.0);  // a field too large for the limit
}

TEST(Solids, OpenMeshBecomesAShell) {
    pbf::MeshInfo info;
    auto shell = pbf::loadMeshSolid(kData + "open_square.obj", {}, {0.01f, 0.05f, 0.02f}, &info);
    EXPECT_FALSE(info.closed());
    EXPECT_EQ(info.boundaryEdges, 4u);
    Vec3 n;
    EXPECT_LT(shell->signedDistance({0.5f, 0.0f, 0.5f}, n),
              0.0f);  // on the sheet: inside the shell
    EXPECT_NEAR(shell->signedDistance({0.5f, 0.03f, 0.5f}, n), 0.02f,
                0.006f);  // 3 cm above, shell 1 cm
}

// A mesh's rotation and translation are its pose (the scale is baked into
// the level set): the unit cube scaled to 0.1 x 0.3 x 0.1, turned 90 degrees
// about y (x -> -z, z -> x: the box's x in [0, 0.1] becomes z in [-0.1, 0])
// and moved by (0.2, 0, 0.3), is the box [0.2, 0.3] x [0, 0.3] x [0.2, 0.3].
// A rotation applied the wrong way round would put it at z in [0.3, 0.4].
TEST(Solids, MeshRotationAndTranslationAreItsPose) {
    const std::string json = pbf::test::smallSceneJson(
        R"("solids": [{"type": "mesh", "file": "cube.obj", "scale": [0.1, 0.3, 0.1],
                       "rotation": [0, 90, 0], "translation": [0.2, 0, 0.3]}])");
    const pbf::Scene scene = pbf::parseScene(json, kData + "posed.json");
    const auto solids = pbf::buildSolids(scene);
    ASSERT_EQ(solids->size(), 1u);
    EXPECT_FALSE(solids->motion(0).pose.identity());
    const auto box = pbf::makeBoxSolid({{0.2f, 0.0f, 0.2f}, {0.3f, 0.3f, 0.3f}});
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.1f, 0.4f);
    const float voxel = 0.5f * scene.simulation.particleRadius;
    int inside = 0;
    for (int k = 0; k < 400; ++k) {
        const Vec3 p{u(rng), u(rng) - 0.1f, u(rng)};
        Vec3 nBox, nMesh;
        const float expected = box->signedDistance(p, nBox);
        if (std::fabs(expected) > 0.03f) continue;  // inside the level set's narrow band
        const float d = solids->signedDistance(p, 1.0f, nMesh);
        EXPECT_NEAR(d, expected, voxel) << p.x << " " << p.y << " " << p.z;
        inside += expected < 0.0f ? 1 : 0;
    }
    EXPECT_GT(inside, 10);
}

// A moving solid carries the water it touches: with full friction a particle
// landing on a box that slides at 1 m/s leaves with the box's velocity
// (respondToSolids works on the velocity relative to the surface).
TEST(Solids, MovingSolidDragsTheWaterItTouches) {
    pbf::SolidSet solids;
    solids.add(pbf::makeBoxSolid({{0, 0, 0}, {1, 0.5f, 1}}));
    const Vec3 onTop{0.5f, 0.5f + 0.01f, 0.5f};
    const Vec3 falling{0.0f, -1.0f, 0.0f};
    // Static: the fall is stopped, nothing slides.
    EXPECT_EQ(pbf::boundary::respondToSolids(solids, 0.01f, 0.0f, 1.0f, onTop, falling),
              (Vec3{0, 0, 0}));
    pbf::SolidMotion sliding;
    sliding.velocity = {1.0f, 0.0f, 0.0f};
    solids.setMotion(0, sliding);
    EXPECT_TRUE(solids.anyMoving());
    const Vec3 v = pbf::boundary::respondToSolids(solids, 0.01f, 0.0f, 1.0f, onTop, falling);
    EXPECT_NEAR(v.x, 1.0f, 1e-6f);
    EXPECT_NEAR(v.y, 0.0f, 1e-6f);
    // A spinning solid: the surface velocity is omega x (p - origin).
    pbf::SolidMotion spinning;
    spinning.angularVelocity = {0.0f, 2.0f, 0.0f};
    spinning.pose.position = {0.5f, 0.0f, 0.5f};
    EXPECT_EQ(spinning.velocityAt({0.5f, 0.3f, 0.0f}), (Vec3{-1.0f, 0.0f, 0.0f}));
}

TEST(Solids, SceneErrorsNameTheField) {
    const std::string json =
        pbf::test::smallSceneJson(R"("solids": [{"type": "mesh", "file": "nowhere.obj"}])");
    const pbf::Scene scene = pbf::parseScene(json, "s.json");
    try {
        pbf::buildSolids(scene);
        FAIL();
    } catch (const pbf::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("s.json: solids[0].file: nowhere.obj"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW(
        pbf::parseScene(pbf::test::smallSceneJson(R"("solids": [{"type": "torus"}])"), "s.json"),
        pbf::SceneError);
    EXPECT_THROW(
        pbf::parseScene(pbf::test::smallSceneJson(
                            R"("solids": [{"type": "sphere", "center": [0,0,0], "radius": -1}])"),
                        "s.json"),
        pbf::SceneError);
}

TEST(Solids, ParticlesAreNotSpawnedInsideSolids) {
    const std::string json = pbf::test::smallSceneJson(
        R"("solids": [{"type": "sphere", "center": [0.1, 0.1, 0.1], "radius": 0.06}])");
    const pbf::Scene scene = pbf::parseScene(json, "s.json");
    pbf::World sim(scene);
    EXPECT_GT(sim.skippedParticles(), 0u);
    EXPECT_EQ(sim.particles().size() + sim.skippedParticles(), 125u);
    for (std::size_t i = 0; i < sim.particles().size(); ++i)
        EXPECT_GE(pbf::length(sim.particles().position.get(i) - Vec3{0.1f, 0.1f, 0.1f}),
                  0.06f + 0.02f - 1e-5f);
}

// Every frame of a run: nothing inside a solid, nothing past `maxX`.
void expectNoLeaks(const std::string& sceneFile, std::vector<pbf::SceneOverride> overrides,
                   double seconds, float maxX = 1e30f) {
    pbf::World sim(pbf::loadScene(pbf::test::scenePath(sceneFile), overrides));
    while (sim.time() < seconds) {
        const pbf::FrameReport r = pbf::test::stepFrame(sim);
        ASSERT_EQ(r.state.insideSolid, 0u) << sceneFile << " frame " << r.frame;
        const auto& x = sim.particles().position.x;
        ASSERT_LE(*std::max_element(x.begin(), x.end()), maxX) << sceneFile << " frame " << r.frame;
    }
    EXPECT_GT(sim.particles().size(), 0u);
}

TEST(Solids, ThinWallHitAtTenMetresPerSecondIsNeverCrossed) {
    // A 3 mm wall (less than a particle radius) hit at 10 m/s.
    expectNoLeaks("thin_wall.json", {pbf::parseOverride("particle_radius=0.015")}, 0.6, 0.6f);
}

TEST(Solids, ShippedSolidScenesNeverLeak) {
    expectNoLeaks("obstacle_flow.json", {pbf::parseOverride("particle_radius=0.02")}, 1.0);
    expectNoLeaks("pour_bunny.json", {pbf::parseOverride("particle_radius=0.012")}, 1.5);
}

// A block resting on the floor around a box-shaped solid standing in it,
// given as an analytic box or as a mesh: returns {density near, interior}.
std::pair<double, double> restAgainstSolid(const std::string& solid) {
    const std::string json = R"({
      "domain": {"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]},
      "particle_radius": 0.01,
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.4, 0.16, 0.4]}],
      "solids": [)" + solid + "]}";
    pbf::World sim(pbf::parseScene(json, kData + "rest_solid.json"));
    EXPECT_GT(sim.skippedParticles(), 0u);
    while (sim.time() < 2.0) EXPECT_EQ(pbf::test::stepFrame(sim).state.insideSolid, 0u);
    // Compare the density next to the solid (within h of its faces) with the interior.
    const pbf::ParticleStore& p = sim.particles();
    auto box = pbf::makeBoxSolid({{0.15f, 0.0f, 0.15f}, {0.25f, 0.3f, 0.25f}});
    double nearSum = 0, farSum = 0;
    int nearCount = 0, farCount = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 x = p.position.get(i);
        if (x.y < 0.04f || x.y > 0.10f) continue;  // away from floor and surface
        Vec3 n;
        const float d = box->signedDistance(x, n);
        if (d < 0.03f) {
            nearSum += p.density[i];
            ++nearCount;
        } else if (d > 0.06f && x.x > 0.04f && x.x < 0.36f && x.z > 0.04f && x.z < 0.36f) {
            farSum += p.density[i];
            ++farCount;
        }
    }
    EXPECT_GT(nearCount, 20);
    EXPECT_GT(farCount, 20);
    return {nearSum / std::max(1, nearCount), farSum / std::max(1, farCount)};
}

TEST(Solids, RestingWaterAtASolidHasInteriorDensity) {
    for (
        const std::string& solid :
        {std::string(R"({"type": "box", "min": [0.15, 0.0, 0.15], "max": [0.25, 0.3, 0.25]})"),
         std::string(
             R"({"type": "mesh", "file": "cube.obj", "scale": [0.1, 0.3, 0.1], "translation": [0.15, 0.0, 0.15]})")}) {
        const auto [nearDensity, farDensity] = restAgainstSolid(solid);
        std::printf("resting at %s: density near the solid %.1f, interior %.1f kg/m^3\n",
                    solid.c_str(), nearDensity, farDensity);
        EXPECT_NEAR(nearDensity, farDensity, 0.02 * farDensity) << solid;
        EXPECT_GT(nearDensity, 980.0) << solid;
    }
}

}  // namespace

// The lookup grid for many solids (SolidSet::buildIndex) gives exactly the
// answers of the plain scan: same distance, normal and nearest solid, for
// every reach (those beyond its margin fall back to the scan), moved solids
// included.
TEST(SolidIndex, SameAnswersAsTheScan) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    pbf::SolidSet indexed, plain;
    for (int k = 0; k < 40; ++k) {
        const pbf::Vec3 c{u(rng), u(rng), u(rng)};
        const float s = 0.01f + 0.05f * u(rng);
        for (pbf::SolidSet* set : {&indexed, &plain}) {
            if (k % 2 == 0)
                set->add(pbf::makeSphereSolid(c, s));
            else
                set->add(pbf::makeBoxSolid({c - pbf::Vec3{s, s, s}, c + pbf::Vec3{s, s, s}}));
        }
    }
    // Move a few, as bodies do, then index.
    for (std::size_t k = 0; k < 40; k += 7) {
        const pbf::SolidMotion m{{{0.05f, -0.02f, 0.01f}, pbf::axisAngle({0, 1, 0}, 0.3f)}, {}, {}};
        indexed.setMotion(k, m);
        plain.setMotion(k, m);
    }
    indexed.buildIndex({{-0.1f, -0.1f, -0.1f}, {1.1f, 1.1f, 1.1f}}, 0.06f);
    int hits = 0;
    for (int q = 0; q < 20000; ++q) {
        const pbf::Vec3 p{u(rng) * 1.2f - 0.1f, u(rng) * 1.2f - 0.1f, u(rng) * 1.2f - 0.1f};
        const float reach = q % 3 == 0 ? 0.1f : 0.06f * u(rng);  // beyond and within the margin
        pbf::Vec3 na, nb;
        std::size_t ka = 999, kb = 999;
        const float da = indexed.signedDistance(p, reach, na, &ka);
        const float db = plain.signedDistance(p, reach, nb, &kb);
        ASSERT_EQ(da, db) << q;
        ASSERT_EQ(ka, kb) << q;
        if (ka != 999) {
            ASSERT_EQ(na, nb) << q;
            ++hits;
        }
    }
    EXPECT_GT(hits, 1000);  // points near solids were asked about
}
