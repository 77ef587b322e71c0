// Scene loading: shipped scenes load; every kind of bad input is refused with
// an error that names the file and the field.
#include "pbf/io/scene.hpp"

#include <gtest/gtest.h>

#include "support/test_util.hpp"

namespace {

using pbf::parseScene;
using pbf::SceneError;
using pbf::test::smallSceneJson;

// Expects parsing to fail with a message containing every fragment.
void expectError(const std::string& json, std::initializer_list<std::string> fragments,
                 const std::vector<pbf::SceneOverride>& overrides = {}) {
    try {
        parseScene(json, "bad.json", overrides);
        FAIL() << "no error for: " << json;
    } catch (const SceneError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind("bad.json: ", 0), 0u) << message;
        for (const std::string& f : fragments)
            EXPECT_NE(message.find(f), std::string::npos) << message;
    }
}

TEST(Scene, ShippedScenesLoad) {
    for (const char* name :
         {"dam_break.json", "cube_drop.json", "cube_drop_fine.json", "resting.json"}) {
        const pbf::Scene scene = pbf::loadScene(pbf::test::scenePath(name));
        EXPECT_FALSE(scene.fluidBlocks.empty()) << name;
        EXPECT_GT(pbf::countParticles(scene), 1000u) << name;
    }
}

TEST(Scene, DefaultsAndParticleCount) {
    const pbf::Scene scene = parseScene(smallSceneJson(), "small.json");
    EXPECT_EQ(scene.name, "small");
    EXPECT_EQ(scene.simulation.solver.iterations, 4);
    EXPECT_FLOAT_EQ(scene.simulation.fluid.restDensity, 1000.0f);
    EXPECT_EQ(scene.output.directory, "out/small");
    EXPECT_EQ(pbf::countParticles(scene), 125u);  // 0.2 / 0.04 = 5 per axis
    const pbf::ParticleStore p = pbf::createParticles(scene);
    ASSERT_EQ(p.size(), 125u);
    EXPECT_FLOAT_EQ(p.position.x[0], 0.02f);  // first particle one radius from the corner
    EXPECT_EQ(p.id[124], 124u);
}

TEST(Scene, MalformedJson) {
    expectError("{\"domain\": ", {"not valid JSON"});
}
TEST(Scene, NotAnObject) {
    expectError("[1, 2]", {"document", "expected an object"});
}
TEST(Scene, UnknownTopLevelKey) {
    expectError(smallSceneJson(R"("gravty": [0, -9.8, 0])"), {"gravty", "unknown key"});
}
TEST(Scene, UnknownNestedKey) {
    expectError(smallSceneJson(R"("solver": {"iteration": 3})"),
                {"solver.iteration", "unknown key"});
}
TEST(Scene, WrongType) {
    expectError(smallSceneJson(R"("solver": {"iterations": "many"})"),
                {"solver.iterations", "expected an integer"});
    expectError(smallSceneJson(R"("gravity": [0, -9.8])"), {"gravity", "3 numbers"});
    expectError(smallSceneJson(R"("output": {"particles": 1})"),
                {"output.particles", "true or false"});
}
TEST(Scene, OutOfRange) {
    expectError(smallSceneJson(R"("solver": {"iterations": 0})"),
                {"solver.iterations", "[1, 100]", "got 0"});
    expectError(smallSceneJson(R"("fluid": {"viscosity": -1})"), {"fluid.viscosity"});
    expectError(smallSceneJson(R"("solver": {"cfl": 2})"), {"solver.cfl"});
    expectError(smallSceneJson(R"("solver": {"time_step": "sometimes"})"),
                {"solver.time_step", "adaptive"});
    expectError(smallSceneJson(R"("output": {"fps": 0})"), {"output.fps"});
}
// Images while simulating (output.render): defaults, values, and every bad
// value named by its field. The fingerprint ignores them (they do not change
// the simulated states, so --resume may add or drop them).
TEST(Scene, RenderOutputFields) {
    const pbf::Scene plain = parseScene(smallSceneJson(), "small.json");
    EXPECT_FALSE(plain.output.render.enabled());
    EXPECT_EQ(plain.output.render.width, 960);
    EXPECT_EQ(plain.output.render.height, 540);
    EXPECT_FALSE(plain.output.render.cameraPosition.has_value());
    const pbf::Scene scene =
        parseScene(smallSceneJson(R"("output": {"render": "liquid", "render_color": "density",
            "image_size": [320, 200], "camera_position": [1, 2, 3], "camera_target": [0, 0, 0],
            "camera_fov": 30})"),
                   "small.json");
    const pbf::RenderOutput& r = scene.output.render;
    EXPECT_EQ(r.style, "liquid");
    EXPECT_EQ(r.color, "density");
    EXPECT_EQ(r.width, 320);
    EXPECT_EQ(r.height, 200);
    ASSERT_TRUE(r.cameraPosition && r.cameraTarget);
    EXPECT_FLOAT_EQ(r.cameraPosition->z, 3.0f);
    EXPECT_FLOAT_EQ(r.fov, 30.0f);
    EXPECT_EQ(scene.fingerprint, plain.fingerprint);
    EXPECT_FALSE(parseScene(smallSceneJson(R"("output": {"render": "none"})"), "s.json")
                     .output.render.enabled());
}
TEST(Scene, BadRenderOutputFields) {
    expectError(smallSceneJson(R"("output": {"render": "glass"})"), {"output.render", "glass"});
    expectError(smallSceneJson(R"("output": {"render": true})"), {"output.render", "string"});
    expectError(smallSceneJson(R"("output": {"render_color": "red"})"), {"output.render_color"});
    expectError(smallSceneJson(R"("output": {"image_size": [960]})"), {"output.image_size"});
    expectError(smallSceneJson(R"("output": {"image_size": [960.5, 540]})"),
                {"output.image_size", "[width, height]"});
    expectError(smallSceneJson(R"("output": {"image_size": [10000, 540]})"),
                {"output.image_size", "[16, 8192]"});
    expectError(smallSceneJson(R"("output": {"camera_fov": 180})"), {"output.camera_fov"});
    expectError(smallSceneJson(R"("output": {"camera_position": [0, 1]})"),
                {"output.camera_position", "3 numbers"});
    expectError(
        smallSceneJson(R"("output": {"camera_position": [0, 5, 0], "camera_target": [0, 0, 0]})"),
        {"output.camera_position", "vertical"});
    expectError(smallSceneJson(R"("output": {"camera": [0, 5, 0]})"),
                {"output.camera", "unknown key"});
}
TEST(Scene, MissingRequiredFields) {
    expectError(R"({"particle_radius": 0.02, "fluid_blocks": []})", {"domain", "missing"});
    expectError(R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "fluid_blocks": []})",
                {"particle_radius", "missing"});
    expectError(R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "particle_radius": 0.02})",
                {"fluid_blocks", "at least one"});
}
TEST(Scene, InvertedDomain) {
    expectError(
        R"({"domain": {"min": [0,0,0], "max": [1,-1,1]}, "particle_radius": 0.02, "fluid_blocks": []})",
        {"domain.max", "greater than min"});
    expectError(
        R"({"domain": {"min": [0,0,0], "max": [1,0,1]}, "particle_radius": 0.02, "fluid_blocks": []})",
        {"domain.max", "greater than min"});
}
TEST(Scene, OverlappingBlocks) {
    const std::string json =
        R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "particle_radius": 0.02,
      "fluid_blocks": [{"min": [0,0,0], "max": [0.5,0.5,0.5]}, {"min": [0.4,0.4,0.4], "max": [0.8,0.8,0.8]}]})";
    expectError(json, {"fluid_blocks[1]", "overlaps fluid_blocks[0]"});
}
TEST(Scene, EmptyBlock) {
    const std::string json =
        R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "particle_radius": 0.02,
      "fluid_blocks": [{"min": [0,0,0], "max": [0.5,0.01,0.5]}]})";
    expectError(json, {"fluid_blocks[0]", "empty"});
}
TEST(Scene, BlockOutsideDomain) {
    const std::string json =
        R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "particle_radius": 0.02,
      "fluid_blocks": [{"min": [0.5,0.5,0.5], "max": [1.5,0.8,0.8]}]})";
    expectError(json, {"fluid_blocks[0]", "inside the domain"});
}
TEST(Scene, NonsenseParticleRadius) {
    expectError(smallSceneJson().replace(smallSceneJson().find("0.02"), 4, "-1.0"),
                {"particle_radius"});
    expectError(smallSceneJson().replace(smallSceneJson().find("0.02"), 4, "1e999"),
                {"particle_radius", "number out of range"});
    expectError(smallSceneJson().replace(smallSceneJson().find("0.02"), 4, "1e30"),
                {"particle_radius"});
}

TEST(Scene, OverridesApplyAndAreValidated) {
    const pbf::Scene scene = parseScene(
        smallSceneJson(), "small.json",
        {pbf::parseOverride("solver.iterations=7"), pbf::parseOverride("gravity=[0,-1,0]"),
         pbf::parseOverride("output.directory=elsewhere"),
         pbf::parseOverride("fluid_blocks.0.velocity=[1,0,0]")});
    EXPECT_EQ(scene.simulation.solver.iterations, 7);
    EXPECT_FLOAT_EQ(scene.simulation.gravity.y, -1.0f);
    EXPECT_EQ(scene.output.directory, "elsewhere");
    EXPECT_FLOAT_EQ(scene.fluidBlocks[0].velocity.x, 1.0f);
    expectError(smallSceneJson(), {"solver.iterations", "got 0"},
                {pbf::parseOverride("solver.iterations=0")});
    expectError(smallSceneJson(), {"solver.itrations", "unknown key"},
                {pbf::parseOverride("solver.itrations=3")});
    expectError(smallSceneJson(), {"index 3 out of range"},
                {pbf::parseOverride("fluid_blocks.3.velocity=[1,0,0]")});
    EXPECT_THROW(pbf::parseOverride("no-equals-sign"), SceneError);
}

TEST(Scene, MissingFile) {
    try {
        pbf::loadScene("/nonexistent/dir/scene.json");
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/scene.json: cannot open scene file"),
                  std::string::npos);
    }
}

TEST(Scene, SizesThatDoNotFitInMemoryAreRefused) {
    // 10^12 particles: refused before anything is allocated.
    const std::string json =
        R"({"domain": {"min": [0,0,0], "max": [100,100,100]}, "particle_radius": 0.0005,
      "fluid_blocks": [{"min": [0,0,0], "max": [100,100,100]}]})";
    try {
        const pbf::Scene scene = parseScene(json, "huge.json");
        pbf::checkMemory(scene, std::size_t{24} << 30);
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("huge.json"), std::string::npos) << e.what();
    }
    const pbf::Scene small = parseScene(smallSceneJson(), "small.json");
    EXPECT_NO_THROW(pbf::checkMemory(small, std::size_t{1} << 30));
    EXPECT_THROW(pbf::checkMemory(small, 1000), SceneError);
}

}  // namespace
