// pbf::loadTriangleMesh: OBJ files placed by scale, rotation and translation,
// and bad files named.
#include "pbf/geometry/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <string>

namespace pbf {
namespace {

TEST(TriangleMesh, LoadsAndPlacesObjFilesAndNamesBadOnes) {
    const std::string data = std::string(PBF_TESTS_DATA_DIR) + "/";
    Transform transform;
    transform.scale = {0.5f, 0.5f, 0.5f};
    transform.rotationDegrees = {0.0f, 90.0f, 0.0f};
    transform.translation = {1.0f, 2.0f, 3.0f};
    const TriangleMesh mesh = loadTriangleMesh(data + "cube.obj", transform);
    ASSERT_EQ(mesh.vertices.size(), 8u);
    EXPECT_EQ(mesh.triangles.size(), 12u);
    // Vertex 7 of the file is (1, 1, 1): scaled to 0.5, turned 90 degrees about y
    // (x -> -z, z -> x), moved.
    EXPECT_NEAR(mesh.vertices[6].x, 1.5f, 1e-5f);
    EXPECT_NEAR(mesh.vertices[6].y, 2.5f, 1e-5f);
    EXPECT_NEAR(mesh.vertices[6].z, 2.5f, 1e-5f);
    const auto expectError = [&](const std::string& file, const std::string& text) {
        try {
            (void)loadTriangleMesh(data + file, Transform{});
            ADD_FAILURE() << file << ": no error";
        } catch (const SolidError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(file), std::string::npos) << what;
            EXPECT_NE(what.find(text), std::string::npos) << what;
        }
    };
    expectError("empty.obj", "no triangles");
    expectError("nan_vertex.obj", "not finite");
    expectError("bad_index.obj", "missing vertex");
    expectError("cube.stl", "no such file");
    expectError("missing_mesh.json", "unsupported mesh format");
}

}  // namespace
}  // namespace pbf
