// USD text layers (include/pbf/io/usd.hpp), read back here by a parser of
// the test's own: floats survive as the same bits, the clip metadata names
// every frame's layer. tests/clients/usd/check_stage.mjs opens whole stages
// with an independent USD reader (TinyUSDZ).
#include "pbf/io/usd.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_util.hpp"

namespace pbf {
namespace {

namespace fs = std::filesystem;

using pbf::test::freshDirectory;

std::string readText(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// The numbers of the line after "<declaration>.timeSamples = {".
std::vector<std::string> sampleNumbers(const std::string& text, const std::string& declaration) {
    const std::size_t at = text.find(declaration + ".timeSamples = {\n");
    EXPECT_NE(at, std::string::npos) << declaration;
    if (at == std::string::npos) return {};
    const std::size_t start = text.find(": ", text.find('\n', at)) + 2;
    const std::string line = text.substr(start, text.find('\n', start) - start);
    std::vector<std::string> numbers;
    std::string current;
    for (const char c : line + ",") {
        if ((c >= '0' && c <= '9') || c == '.' || c == '-' || c == 'e' || c == '+') {
            current += c;
        } else if (!current.empty()) {
            numbers.push_back(current);
            current.clear();
        }
    }
    return numbers;
}

TEST(Usd, PointsClipKeepsEveryFloatsBits) {
    const fs::path dir = freshDirectory("points");
    // Values whose shortest decimal form is long, tiny, huge, negative zero.
    const std::vector<Vec3> positions = {
        {0.1f, 1.0f / 3.0f, -0.0f},
        {std::numeric_limits<float>::max(), 1e-7f, -2.5f},
        {std::numeric_limits<float>::denorm_min(), 0.7f, 123.456f}};
    const std::vector<Vec3> velocities = {{1, 2, 3}, {-1e-30f, 0, 0}, {0.2f, 0.3f, 0.4f}};
    const std::vector<std::uint64_t> ids = {7, 4294967301u, 123456};  // one past 32 bits
    const std::vector<float> density = {1000.25f, 999.999f, 1e3f};
    usd::writePointsClip(dir / "00012.usda", "particles", 12,
                         {positions, velocities, ids, density, {}, 0.02f});
    const std::string text = readText(dir / "00012.usda");
    EXPECT_EQ(text.rfind("#usda 1.0\n", 0), 0u);
    EXPECT_NE(text.find("def Points \"particles\""), std::string::npos);

    const std::vector<std::string> p = sampleNumbers(text, "point3f[] points");
    ASSERT_EQ(p.size(), 9u);
    for (std::size_t i = 0; i < 9; ++i) {
        const float expected = (&positions[i / 3].x)[i % 3];
        const float read = std::strtof(p[i].c_str(), nullptr);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(read), std::bit_cast<std::uint32_t>(expected))
            << p[i];
    }
    EXPECT_EQ(sampleNumbers(text, "int64[] ids"),
              (std::vector<std::string>{"7", "4294967301", "123456"}));
    const std::vector<std::string> d = sampleNumbers(text, "float[] primvars:density");
    ASSERT_EQ(d.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(std::strtof(d[i].c_str(), nullptr), density[i]);
    EXPECT_EQ(sampleNumbers(text, "float[] widths"),
              (std::vector<std::string>{"0.02", "0.02", "0.02"}));
    EXPECT_EQ(sampleNumbers(text, "vector3f[] velocities").size(), 9u);
    // The extent holds the points grown by their radius.
    const std::vector<std::string> e = sampleNumbers(text, "float3[] extent");
    ASSERT_EQ(e.size(), 6u);
    EXPECT_LE(std::strtof(e[1].c_str(), nullptr), 1e-7f - 0.01f);
    EXPECT_GE(std::strtof(e[5].c_str(), nullptr), 123.456f + 0.01f - 1e-5f);
    fs::remove_all(dir);
}

TEST(Usd, MeshClipHasTrianglesAndNormals) {
    const fs::path dir = freshDirectory("mesh");
    const std::vector<Vec3> vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::vector<Vec3> normals = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 2, 1}, {0, 1, 3}};
    usd::writeMeshClip(dir / "00003.usda", "surface", 3, {vertices, normals, triangles});
    const std::string text = readText(dir / "00003.usda");
    EXPECT_EQ(sampleNumbers(text, "int[] faceVertexCounts"), (std::vector<std::string>{"3", "3"}));
    EXPECT_EQ(sampleNumbers(text, "int[] faceVertexIndices"),
              (std::vector<std::string>{"0", "2", "1", "0", "1", "3"}));
    EXPECT_EQ(sampleNumbers(text, "normal3f[] normals").size(), 12u);
    EXPECT_EQ(sampleNumbers(text, "point3f[] points").size(), 12u);
    fs::remove_all(dir);
}

TEST(Usd, RootLayerHasTimeMetadataAndClips) {
    const fs::path dir = freshDirectory("root");
    usd::Stage stage;
    stage.doc = "a \"quoted\" name";
    stage.fps = 24.0;
    stage.endFrame = 2;
    usd::ClipSeries series{"particles",
                           "Points",
                           {0, 1, 2},
                           "run_usd/particles",
                           usd::pointsAttributes(true, true, true, false)};
    stage.series.push_back(series);
    usd::BodyTrack body;
    body.name = "body_0";
    body.frames = {0, 1};
    body.position = {{0.1, 0.2, 0.3}, {0.1, 0.25, 0.3}};
    body.orientation = {{1, 0, 0, 0}, {0.5, 0.5, 0.5, 0.5}};
    stage.bodies.push_back(body);
    stage.camera = usd::Camera{{0.5f, 0.5f, 2.0f}, {0.5f, 0.5f, 0.5f}, 40.0f, 16.0f / 9.0f};
    usd::writeRootLayer(dir / "run.usda", stage);
    fs::create_directories(dir / series.directory);
    usd::writeClipManifest(dir, series);
    const std::string text = readText(dir / "run.usda");
    for (const char* line :
         {"    timeCodesPerSecond = 24\n", "    framesPerSecond = 24\n", "    startTimeCode = 0\n",
          "    endTimeCode = 2\n", "    upAxis = \"Y\"\n", "    metersPerUnit = 1\n",
          "    defaultPrim = \"run\"\n", "    doc = \"a \\\"quoted\\\" name\"\n",
          "double2[] active = [(0, 0), (1, 1), (2, 2)]",
          "asset[] assetPaths = [@./run_usd/particles/00000.usda@, "
          "@./run_usd/particles/00001.usda@, @./run_usd/particles/00002.usda@]",
          "double2[] times = [(0, 0), (1, 1), (2, 2)]", "string primPath = \"/particles\"",
          "asset manifestAssetPath = @./run_usd/particles/manifest.usda@",
          "                1: (0.1, 0.25, 0.3),\n", "                1: (0.5, 0.5, 0.5, 0.5),\n",
          "def Camera \"camera\""})
        EXPECT_NE(text.find(line), std::string::npos) << line << "\nin\n" << text;
    const std::string manifest = readText(dir / "run_usd/particles/manifest.usda");
    EXPECT_NE(manifest.find("over \"particles\""), std::string::npos);
    EXPECT_NE(manifest.find("    int64[] ids\n"), std::string::npos);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace pbf
