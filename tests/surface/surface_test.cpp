// Surface reconstruction and OpenVDB caches: meshes of known shapes have the
// right volume, area and flatness and are watertight; spray is dropped; VDB
// point caches read back what was written; bad input is refused.
#include "pbf/surface/surface.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include "pbf/io/io.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/run/run.hpp"
#include "pbf/surface/anisotropic.hpp"
#include "pbf/surface/diffuse.hpp"
#include "pbf/surface/mesh_frames.hpp"
#include "pbf/surface/vdb_points.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace {

namespace fs = std::filesystem;
using pbf::Vec3;
using namespace pbf::surface;

constexpr float kR = 0.01f;  // particle radius of the test shapes

fs::path freshDirectory(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / ("pbf_surface_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Lattice points of spacing 2 r inside `inside`, each moved by up to
// `jitter` r per axis (as a settled PBF fluid is never a perfect lattice).
template <class Inside>
std::vector<Vec3> lattice(Vec3 lo, Vec3 hi, float jitter, Inside inside) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-jitter * kR, jitter * kR);
    std::vector<Vec3> points;
    for (float z = lo.z + kR; z < hi.z; z += 2 * kR)
        for (float y = lo.y + kR; y < hi.y; y += 2 * kR)
            for (float x = lo.x + kR; x < hi.x; x += 2 * kR)
                if (inside(Vec3{x, y, z})) points.push_back({x + u(rng), y + u(rng), z + u(rng)});
    return points;
}

std::vector<Vec3> ball(float radius) {
    return lattice({-radius, -radius, -radius}, {radius, radius, radius}, 0.15f,
                   [&](Vec3 p) { return length(p) < radius - kR; });
}

SurfaceParams defaults(SurfaceMethod method = SurfaceMethod::anisotropic) {
    SurfaceParams p;
    p.particleRadius = kR;
    p.method = method;
    return p;
}

// The shape tests run for both methods: the anisotropic default and the
// isotropic one it replaced, which stays available.
class SurfaceMethods : public ::testing::TestWithParam<SurfaceMethod> {};
INSTANTIATE_TEST_SUITE_P(Surface, SurfaceMethods,
                         ::testing::Values(SurfaceMethod::anisotropic, SurfaceMethod::isotropic),
                         [](const auto& test) { return std::string(toString(test.param)); });

TEST_P(SurfaceMethods, BallMeshesToAClosedSphereOfTheFluidVolume) {
    const std::vector<Vec3> particles = ball(0.12f);
    const TriangleMesh mesh = reconstructSurface(particles, defaults(GetParam()));
    ASSERT_FALSE(mesh.triangles.empty());
    const EdgeReport edges = checkEdges(mesh);
    EXPECT_TRUE(edges.watertight())
        << edges.boundaryEdges << " boundary, " << edges.nonManifoldEdges << " non-manifold, "
        << edges.misorientedEdges << " misoriented";
    EXPECT_EQ(countComponents(mesh), 1u);
    // A closed surface of genus 0: V - E + F = 2.
    EXPECT_EQ(long(mesh.vertices.size()) - long(edges.edges) + long(mesh.triangles.size()), 2);
    // Every particle stands for a cube of (2 r)^3 water.
    const double fluidVolume = double(particles.size()) * 8.0 * kR * kR * kR;
    const double radius = std::cbrt(3.0 * fluidVolume / (4.0 * std::numbers::pi));
    const double volumeRatio = meshVolume(mesh) / fluidVolume;
    const double areaRatio = meshArea(mesh) / (4.0 * std::numbers::pi * radius * radius);
    std::printf("%s ball: volume %.4f of the fluid's, area %.4f of the sphere's\n",
                toString(GetParam()), volumeRatio, areaRatio);
    EXPECT_NEAR(volumeRatio, 1.0, 0.03);
    // A little more area than the sphere: the lattice's staircase shows.
    EXPECT_NEAR(areaRatio, 1.0, 0.05);
    // Round: vertices within a particle radius of the sphere on average
    // (RMS), and nowhere further than the staircase of the lattice allows.
    double squares = 0.0, worst = 0.0;
    for (const Vec3& v : mesh.vertices) {
        const double d = double(length(v)) - radius;
        squares += d * d;
        worst = std::max(worst, std::abs(d));
    }
    EXPECT_LT(std::sqrt(squares / double(mesh.vertices.size())), 0.5 * kR);
    EXPECT_LT(worst, 1.5 * kR);
    // Vertex normals from the level set: unit, pointing out of the water,
    // along the mesh's own shape (its area-weighted triangle normals) and
    // near the sphere's radial direction (the lattice's staircase tilts them).
    ASSERT_EQ(mesh.normals.size(), mesh.vertices.size());
    std::vector<Vec3> faceSums(mesh.vertices.size(), Vec3{0, 0, 0});
    for (const auto& t : mesh.triangles) {
        const Vec3 n = cross(mesh.vertices[t[1]] - mesh.vertices[t[0]],
                             mesh.vertices[t[2]] - mesh.vertices[t[0]]);
        for (const std::uint32_t v : t) faceSums[v] = faceSums[v] + n;
    }
    double radial = 0.0, shape = 0.0, leastRadial = 1.0;
    for (std::size_t k = 0; k < mesh.vertices.size(); ++k) {
        EXPECT_NEAR(length(mesh.normals[k]), 1.0f, 1e-5f);
        const double c = dot(mesh.normals[k], mesh.vertices[k]) / length(mesh.vertices[k]);
        radial += c;
        leastRadial = std::min(leastRadial, c);
        shape += dot(mesh.normals[k], faceSums[k]) / length(faceSums[k]);
    }
    const double n = double(mesh.vertices.size());
    std::printf("normals: mean cosine to the mesh's %.4f, to radial %.4f (least %.3f)\n", shape / n,
                radial / n, leastRadial);
    EXPECT_GT(shape / n, 0.995);
    EXPECT_GT(radial / n, 0.97);
    EXPECT_GT(leastRadial, 0.8);
}

TEST_P(SurfaceMethods, RestingSlabHasAFlatTopAtTheFluidHeight) {
    const float height = 0.1f;
    const std::vector<Vec3> particles =
        lattice({0, 0, 0}, {0.3f, height, 0.3f}, 0.1f, [](Vec3) { return true; });
    const TriangleMesh mesh = reconstructSurface(particles, defaults(GetParam()));
    EXPECT_TRUE(checkEdges(mesh).watertight());
    EXPECT_EQ(countComponents(mesh), 1u);
    // The top, away from the rounded edges: within 0.3 r of the fluid's top
    // (top particle centres + r) everywhere, within 0.15 r on average.
    double sum = 0.0, maxDeviation = 0.0;
    int count = 0;
    for (const Vec3& v : mesh.vertices) {
        if (v.y < 0.5f * height || v.x < 0.05f || v.x > 0.25f || v.z < 0.05f || v.z > 0.25f)
            continue;
        sum += v.y;
        maxDeviation = std::max(maxDeviation, std::abs(double(v.y) - height));
        ++count;
    }
    ASSERT_GT(count, 100);
    EXPECT_NEAR(sum / count, height, 0.15 * kR);
    EXPECT_LT(maxDeviation, 0.3 * kR);
}

// Deviation of the free surface of a meshed tank from a horizontal plane.
struct FlatnessFigures {
    double mean = 0.0, rms = 0.0, worst = 0.0;  // m
    int vertices = 0;
};

// The mesh's top vertices (above half the depth, 4 r or more from the walls
// of the box [0, side]^2): their mean height and RMS / largest deviation
// from it.
FlatnessFigures topFlatness(const TriangleMesh& mesh, float depth, float side) {
    FlatnessFigures f;
    std::vector<double> heights;
    for (const Vec3& v : mesh.vertices)
        if (v.y > 0.5f * depth && v.x > 4 * kR && v.x < side - 4 * kR && v.z > 4 * kR &&
            v.z < side - 4 * kR)
            heights.push_back(v.y);
    f.vertices = int(heights.size());
    if (heights.empty()) return f;
    for (double h : heights) f.mean += h;
    f.mean /= double(heights.size());
    for (double h : heights) {
        f.rms += (h - f.mean) * (h - f.mean);
        f.worst = std::max(f.worst, std::abs(h - f.mean));
    }
    f.rms = std::sqrt(f.rms / double(heights.size()));
    return f;
}

// A tank settled by the solver (not a lattice: the particles carry PBF's
// own packing noise), meshed with both methods. Checked: the
// anisotropic free surface within RMS 0.1 r of its plane and at most 0.5 r
// anywhere, and flatter than the isotropic method's on the same particles.
TEST(Surface, RestingTankMeshesToAFlatFreeSurface) {
    const float side = 0.24f, depth = 0.12f;
    pbf::World world(pbf::parseScene(R"({
      "domain": {"min": [0, 0, 0], "max": [0.24, 0.3, 0.24]},
      "particle_radius": 0.01,
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.24, 0.12, 0.24]}],
      "output": {"fps": 30}})",
                                     "tank.json"));
    while (world.time() < 1.0) ASSERT_TRUE(world.stepFrame().ok());
    std::vector<Vec3> particles;
    for (std::size_t i = 0; i < world.particles().size(); ++i)
        particles.push_back(world.particles().position.get(i));
    FlatnessFigures figures[2];
    for (const SurfaceMethod method : {SurfaceMethod::anisotropic, SurfaceMethod::isotropic}) {
        const TriangleMesh mesh = reconstructSurface(particles, defaults(method));
        EXPECT_TRUE(checkEdges(mesh).watertight());
        const FlatnessFigures f = topFlatness(mesh, depth, side);
        std::printf(
            "resting tank, %s: %d top vertices at %.3f r above the fluid height, RMS "
            "%.3f r, largest %.3f r from their plane\n",
            toString(method), f.vertices, (f.mean - depth) / kR, f.rms / kR, f.worst / kR);
        ASSERT_GT(f.vertices, 200);
        figures[method == SurfaceMethod::isotropic] = f;
    }
    const FlatnessFigures& aniso = figures[0];
    const FlatnessFigures& iso = figures[1];
    EXPECT_LT(aniso.rms, 0.1 * kR);
    EXPECT_LE(aniso.worst, 0.5 * kR);
    EXPECT_LT(aniso.rms, iso.rms);
    // Where the water is: the particles' volume over the base, within half
    // a radius (the solver compresses the column by about a per cent).
    EXPECT_NEAR(aniso.mean, depth, 0.5 * kR);
}

// A sheet one particle thick and stretched (particles 2.6 r apart: 1.2 r of
// water per unit area, thinner than 2 r) survives meshing as one closed
// sheet without holes, and stays a sheet: the anisotropic kernels are
// long along it and thin across it (Yu & Turk 2013, figure 1).
TEST(Surface, SheetThinnerThanTwoRadiiSurvivesMeshing) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.1f * kR, 0.1f * kR);
    std::vector<Vec3> sheet;
    const int n = 30;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            sheet.push_back({2.6f * kR * float(i) + u(rng), u(rng), 2.6f * kR * float(j) + u(rng)});
    const TriangleMesh mesh = reconstructSurface(sheet, defaults());
    ASSERT_FALSE(mesh.triangles.empty());
    EXPECT_TRUE(checkEdges(mesh).watertight());
    EXPECT_EQ(countComponents(mesh), 1u);
    // Both faces of the whole sheet: twice its area (plus the rim), no holes.
    const double sheetArea = double(2.6f * kR * n) * double(2.6f * kR * n);
    const double areaRatio = meshArea(mesh) / (2.0 * sheetArea);
    // Thickness in the middle, away from the rim.
    double thickness = 0.0;
    for (const Vec3& v : mesh.vertices)
        if (v.x > 10 * kR && v.x < (2.6f * n - 10) * kR && v.z > 10 * kR &&
            v.z < (2.6f * n - 10) * kR)
            thickness = std::max(thickness, 2.0 * std::abs(double(v.y)));
    std::printf("sheet: area %.3f of both faces, thickness %.2f r\n", areaRatio, thickness / kR);
    EXPECT_GT(areaRatio, 0.95);
    EXPECT_LT(areaRatio, 1.2);
    EXPECT_GT(thickness, 0.5 * kR);
    EXPECT_LT(thickness, 2.5 * kR);
}

// Yu & Turk's ellipsoids: round inside the water, flat at its surface with
// the short axis along the normal, and spheres of k_n h for loners.
TEST(Surface, KernelsAreFlatAtTheSurfaceAndRoundInside) {
    const std::vector<Vec3> slab =
        lattice({0, 0, 0}, {0.3f, 0.2f, 0.3f}, 0.0f, [](Vec3) { return true; });
    std::vector<Vec3> particles = slab;
    particles.push_back({1.0f, 1.0f, 1.0f});  // a lone droplet
    const SurfaceParams p = defaults();
    const std::vector<Ellipsoid> kernels = computeEllipsoids(particles, p);
    const auto find = [&](Vec3 x) {
        for (std::size_t i = 0; i < slab.size(); ++i)
            if (length(slab[i] - x) < 0.1f * kR) return kernels[i];
        ADD_FAILURE() << "no particle at the probe";
        return kernels[0];
    };
    const float h = p.kernelRadius * kR;
    const Ellipsoid inside = find({0.15f, 0.1f + kR, 0.15f});
    const Ellipsoid top = find({0.15f, 0.2f - kR, 0.15f});
    for (const Vec3& a : inside.axes) EXPECT_NEAR(length(a), h, 0.02 * h);
    EXPECT_NEAR(length(top.axes[0]), h, 0.05 * h);
    EXPECT_LT(length(top.axes[2]), 0.6f * h);
    EXPECT_NEAR(std::abs(top.axes[2].y) / length(top.axes[2]), 1.0f, 1e-3f);
    // The smoothed centre of a top particle moves into the water, an inner
    // one stays.
    EXPECT_LT(top.centre.y, 0.2f - kR);
    EXPECT_NEAR(inside.centre.y, 0.1f + kR, 1e-5f);
    const Ellipsoid& lone = kernels.back();
    for (const Vec3& a : lone.axes) EXPECT_NEAR(length(a), p.isolatedScale * h, 1e-6f);
}

TEST(Surface, AnisotropicMeshIsTheSameForAnyThreadCount) {
    std::vector<Vec3> particles = ball(0.08f);
    for (Vec3& x : particles) x.y += 0.3f * x.x;  // no symmetry to hide an ordering error
    const auto meshWith = [&](int threads) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                        std::size_t(threads));
        return reconstructSurface(particles, defaults());
    };
    const TriangleMesh one = meshWith(1), two = meshWith(2);
    ASSERT_EQ(one.vertices.size(), two.vertices.size());
    ASSERT_EQ(one.triangles, two.triangles);
    EXPECT_EQ(0, std::memcmp(one.vertices.data(), two.vertices.data(),
                             one.vertices.size() * sizeof(Vec3)));
}

// Adaptivity on both methods' level sets. The anisotropic one loses more
// volume to it (its flat parts are flatter, so more gets merged).
TEST_P(SurfaceMethods, AdaptiveMeshesAreWatertightAndSmaller) {
    const std::vector<Vec3> particles = ball(0.1f);
    const TriangleMesh uniform = reconstructSurface(particles, defaults(GetParam()));
    SurfaceParams p = defaults(GetParam());
    p.adaptivity = 0.1f;
    const TriangleMesh adaptive = reconstructSurface(particles, p);
    EXPECT_TRUE(checkEdges(adaptive).watertight());
    EXPECT_LT(adaptive.triangles.size(), uniform.triangles.size() / 2);
    const double ratio = meshVolume(adaptive) / meshVolume(uniform);
    std::printf("%s, adaptivity 0.1: %.3f of the triangles, %.4f of the volume\n",
                toString(GetParam()),
                double(adaptive.triangles.size()) / double(uniform.triangles.size()), ratio);
    EXPECT_NEAR(ratio, 1.0, GetParam() == SurfaceMethod::isotropic ? 0.02 : 0.05);
}

// A sphere of water keeps the isotropic method's volume and area accuracy
// or better: the anisotropic ball against the isotropic one.
TEST(Surface, AnisotropicBallIsAtLeastAsAccurateAsIsotropic) {
    const std::vector<Vec3> particles = ball(0.12f);
    const double fluidVolume = double(particles.size()) * 8.0 * kR * kR * kR;
    const double radius = std::cbrt(3.0 * fluidVolume / (4.0 * std::numbers::pi));
    const double sphereArea = 4.0 * std::numbers::pi * radius * radius;
    double volumeError[2], areaError[2];
    for (const SurfaceMethod method : {SurfaceMethod::anisotropic, SurfaceMethod::isotropic}) {
        const TriangleMesh mesh = reconstructSurface(particles, defaults(method));
        const int k = method == SurfaceMethod::isotropic;
        volumeError[k] = std::abs(meshVolume(mesh) / fluidVolume - 1.0);
        areaError[k] = std::abs(meshArea(mesh) / sphereArea - 1.0);
    }
    EXPECT_LE(volumeError[0], volumeError[1]);
    EXPECT_LE(areaError[0], areaError[1]);
}

TEST(Surface, StrayParticlesAreDroppedNotMeshedAsBlobs) {
    std::vector<Vec3> particles = ball(0.08f);
    const std::size_t bulk = particles.size();
    for (int k = 0; k < 20; ++k)
        particles.push_back({0.2f + 0.08f * float(k), 0.3f, 0.0f});  // lone droplets
    BuildReport report;
    const TriangleMesh filtered = reconstructSurface(particles, defaults(), &report);
    EXPECT_EQ(report.particles, particles.size());
    EXPECT_EQ(report.sprayDropped, 20u);
    EXPECT_EQ(countComponents(filtered), 1u);
    for (const Vec3& v : filtered.vertices) EXPECT_LT(length(v), 0.1f);
    // Without the filter every droplet becomes its own little blob.
    SurfaceParams keepAll = defaults();
    keepAll.minNeighbors = 0;
    keepAll.smoothing = 0;  // smoothing may shrink a one-particle blob away
    keepAll.anisotropicSmoothing = 0;
    const TriangleMesh blobs = reconstructSurface(particles, keepAll, &report);
    EXPECT_EQ(report.sprayDropped, 0u);
    EXPECT_EQ(countComponents(blobs), 21u);
    EXPECT_GT(bulk, 100u);
}

TEST(Surface, NothingToMeshGivesAnEmptyMesh) {
    EXPECT_TRUE(reconstructSurface({}, defaults()).triangles.empty());
    const std::vector<Vec3> lone{{0, 0, 0}};
    EXPECT_TRUE(reconstructSurface(lone, defaults()).triangles.empty());  // spray only
}

TEST(Surface, InvalidParametersAreRefusedWithTheField) {
    SurfaceParams p = defaults();
    p.particleRadius = 0.0f;
    EXPECT_NE(validate(p).find("radius"), std::string::npos);
    p = defaults();
    p.voxelSize = 1.8f;  // spheres of 2 r would be narrower than 1.5 voxels
    EXPECT_NE(validate(p).find("voxel-size"), std::string::npos);
    p = defaults();
    p.adaptivity = 2.0f;
    EXPECT_NE(validate(p).find("adaptivity"), std::string::npos);
    EXPECT_THROW(reconstructSurface(ball(0.05f), p), std::invalid_argument);
    EXPECT_EQ(validate(defaults()), "");
}

TEST(Surface, ParticleRadiusIsEstimatedFromTheSpacing) {
    std::vector<Vec3> particles =
        lattice({0, 0, 0}, {0.2f, 0.2f, 0.2f}, 0.1f, [](Vec3) { return true; });
    for (int k = 0; k < 30; ++k)
        particles.push_back({1.0f + float(k), 2.0f, 0.0f});  // spray far away
    // Jitter shortens nearest-neighbour distances: the estimate runs a few
    // per cent low (docs/surfaces.md).
    EXPECT_NEAR(estimateParticleRadius(particles), kR, 0.08 * kR);
    EXPECT_THROW(estimateParticleRadius(std::vector<Vec3>{{0, 0, 0}}), std::invalid_argument);
}

TEST(SurfaceFiles, ObjAndPlyHoldTheMesh) {
    const TriangleMesh mesh = reconstructSurface(ball(0.05f), defaults());
    const fs::path dir = freshDirectory("meshfiles");
    writeMeshObj(dir / "m.obj", mesh);
    writeMeshPly(dir / "m.ply", mesh);
    std::ifstream obj(dir / "m.obj");
    std::size_t v = 0, vn = 0, f = 0;
    std::string line, firstFace;
    while (std::getline(obj, line)) {
        v += line.rfind("v ", 0) == 0;
        vn += line.rfind("vn ", 0) == 0;
        if (line.rfind("f ", 0) == 0 && f++ == 0) firstFace = line;
    }
    EXPECT_EQ(v, mesh.vertices.size());
    EXPECT_EQ(vn, mesh.vertices.size());
    EXPECT_EQ(f, mesh.triangles.size());
    const auto& t = mesh.triangles[0];
    EXPECT_EQ(firstFace, "f " + std::to_string(t[0] + 1) + "//" + std::to_string(t[0] + 1) + " " +
                             std::to_string(t[1] + 1) + "//" + std::to_string(t[1] + 1) + " " +
                             std::to_string(t[2] + 1) + "//" + std::to_string(t[2] + 1));
    std::ifstream ply(dir / "m.ply", std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(ply)), {});
    const std::size_t body = text.find("end_header\n") + 11;
    EXPECT_NE(text.find("element face " + std::to_string(mesh.triangles.size()) + "\n"),
              std::string::npos);
    EXPECT_NE(text.find("property float nx\nproperty float ny\nproperty float nz\n"),
              std::string::npos);
    // x y z nx ny nz per vertex, then (3, a, b, c) per triangle.
    EXPECT_EQ(text.size() - body, mesh.vertices.size() * 24 + mesh.triangles.size() * 13);
    float n0[3];
    std::memcpy(n0, text.data() + body + 12, 12);
    EXPECT_EQ((Vec3{n0[0], n0[1], n0[2]}), mesh.normals[0]);
    // Without normals the PLY is positions and faces only.
    TriangleMesh bare = mesh;
    bare.normals.clear();
    writeMeshPly(dir / "bare.ply", bare);
    EXPECT_EQ(fs::file_size(dir / "bare.ply"),
              text.size() - 54 - mesh.vertices.size() * 12);  // 54: the three nx ny nz lines
    fs::remove_all(dir);
}

TEST(VdbPoints, RoundTripKeepsEveryAttribute) {
    pbf::ParticleStore store;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int k = 0; k < 2000; ++k)
        store.add({u(rng), 0.5f * u(rng), 2.0f + u(rng)}, {u(rng), u(rng), u(rng)},
                  1000.0f + u(rng));
    std::vector<std::uint32_t> perm(store.size());
    for (std::uint32_t k = 0; k < perm.size(); ++k)
        perm[k] = (k * 7919u) % 2000u;  // solver-like memory order
    store.reorder(perm);
    const fs::path dir = freshDirectory("vdbpoints");
    writeParticlesVdb(dir / "p.vdb", store);
    const pbf::ParticleFrame back = readParticlesVdb(dir / "p.vdb");
    ASSERT_EQ(back.position.size(), store.size());
    ASSERT_EQ(back.velocity.size(), store.size());
    ASSERT_EQ(back.density.size(), store.size());
    ASSERT_EQ(back.id.size(), store.size());
    const std::vector<std::uint32_t> order = store.orderById();
    for (std::size_t k = 0; k < order.size(); ++k) {
        const std::uint32_t i = order[k];
        EXPECT_EQ(back.id[k], store.id[i]);
        EXPECT_EQ(back.velocity[k], store.velocity.get(i));
        EXPECT_EQ(back.density[k], store.density[i]);
        // Voxel-relative float storage: equal up to float rounding.
        EXPECT_LT(length(back.position[k] - store.position.get(i)), 1e-6f);
    }
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos);
    fs::remove_all(dir);
}

TEST(VdbPoints, MissingAndForeignFilesAreRejectedWithTheName) {
    const fs::path dir = freshDirectory("vdbbad");
    std::ofstream(dir / "junk.vdb") << "this is not a vdb file";
    for (const char* name : {"missing.vdb", "junk.vdb"}) {
        try {
            readParticlesVdb(dir / name);
            FAIL() << name;
        } catch (const pbf::IoError& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    }
    // A level set is a VDB file but holds no points.
    writeLevelSetVdb(dir / "ls.vdb", buildLevelSet(ball(0.05f), defaults()));
    EXPECT_THROW(readParticlesVdb(dir / "ls.vdb"), pbf::IoError);
    fs::remove_all(dir);
}

TEST(VdbPoints, RunWritesAPointCachePerFrameWhenTheSceneAsks) {
    pbf::Scene scene = pbf::parseScene(
        pbf::test::smallSceneJson(R"("output": {"vdb_points": true})"), "small.json");
    ASSERT_TRUE(scene.output.writeVdbPoints);
    EXPECT_FALSE(pbf::parseScene(pbf::test::smallSceneJson(), "small.json").output.writeVdbPoints);
    const fs::path dir = freshDirectory("runvdb");
    scene.output.directory = dir.string();
    scene.output.frames = 2;
    pbf::RunOptions options;
    options.writeFrame = [&](int frame, const pbf::World& world) {
        writeParticlesVdb(dir / ("frame_" + std::to_string(frame) + ".vdb"), world.particles());
    };
    pbf::runScene(scene, options);
    for (int f = 0; f <= 2; ++f) {
        const pbf::ParticleFrame ply = pbf::readParticlesPly(dir / pbf::frameFileName(f));
        const pbf::ParticleFrame vdb =
            readParticlesVdb(dir / ("frame_" + std::to_string(f) + ".vdb"));
        ASSERT_EQ(vdb.position.size(), ply.position.size());
        for (std::size_t k = 0; k < ply.position.size(); ++k) {
            EXPECT_EQ(vdb.id[k], ply.id[k]);
            EXPECT_EQ(vdb.velocity[k], ply.velocity[k]);
            EXPECT_LT(length(vdb.position[k] - ply.position[k]), 1e-6f);
        }
    }
    fs::remove_all(dir);
}

TEST(MeshFrames, FrameRangesParseLikeSlices) {
    const FrameRange all = parseFrameRange("::2");
    EXPECT_TRUE(all.contains(0));
    EXPECT_FALSE(all.contains(1));
    EXPECT_TRUE(all.contains(1000));
    const FrameRange r = parseFrameRange("10:20:5");
    EXPECT_TRUE(r.contains(10));
    EXPECT_TRUE(r.contains(15));
    EXPECT_FALSE(r.contains(20));
    EXPECT_FALSE(r.contains(12));
    const FrameRange one = parseFrameRange("7");
    EXPECT_TRUE(one.contains(7));
    EXPECT_FALSE(one.contains(8));
    for (const char* bad : {"a", "1:2:0", "5:3", "-1", "1:2:3:4", "1.5"})
        EXPECT_THROW(parseFrameRange(bad), std::invalid_argument) << bad;
    EXPECT_THROW(parseMeshFormats("obj,stl"), std::invalid_argument);
    EXPECT_TRUE(parseMeshFormats("ply").ply);
    EXPECT_TRUE(parseMeshFormats("vtk").vtk);
    const MeshFormats defaultFormats;  // `pbf mesh` without --format: PLY and level sets
    EXPECT_TRUE(defaultFormats.ply && defaultFormats.vdb && !defaultFormats.obj &&
                !defaultFormats.vtk);
}

TEST(MeshFrames, MeshesADirectoryOfFramesWithTheEstimatedRadius) {
    const fs::path dir = freshDirectory("frames");
    pbf::ParticleStore store;
    for (const Vec3& p : ball(0.06f)) store.add(p, {}, 1000.0f);
    for (int f = 0; f < 4; ++f) pbf::writeParticlesPly(dir / pbf::frameFileName(f), store);
    MeshJob job;
    job.input = dir;
    job.range = parseFrameRange("1::2");
    job.formats = parseMeshFormats("obj,ply,vdb");
    std::vector<int> seen;
    job.onFrame = [&](const FrameMeshReport& r) { seen.push_back(r.frame); };
    const MeshSummary summary = meshFrames(job);
    EXPECT_EQ(seen, (std::vector<int>{1, 3}));
    EXPECT_EQ(summary.radiusSource, "estimated");  // no summary.json
    EXPECT_NEAR(summary.particleRadius, kR, 0.1 * kR);
    for (int f : {1, 3}) {
        EXPECT_TRUE(fs::exists(dir / "surface" / surfaceFileName(f, "obj")));
        EXPECT_TRUE(fs::exists(dir / "surface" / surfaceFileName(f, "ply")));
        EXPECT_TRUE(fs::exists(dir / "surface" / levelSetFileName(f)));
    }
    // VTK meshes need the frame rate: none in a directory without summary.json.
    job.formats = parseMeshFormats("vtk");
    EXPECT_THROW(meshFrames(job), pbf::IoError);
    job.fps = 30.0f;
    meshFrames(job);
    job.range = parseFrameRange("2");  // a later job adds its frame to surface.pvd
    meshFrames(job);
    std::ifstream pvd(dir / "surface" / "surface.pvd");
    const std::string listing((std::istreambuf_iterator<char>(pvd)), {});
    EXPECT_NE(
        listing.find(R"(<DataSet timestep="0.03333333333333333" part="0" file="surface_00001.vtp"/>
    <DataSet timestep="0.06666666666666667" part="0" file="surface_00002.vtp"/>
    <DataSet timestep="0.1" part="0" file="surface_00003.vtp"/>)"),
        std::string::npos)
        << listing;
    job.formats = parseMeshFormats("obj,ply,vdb");
    job.fps = 0.0f;
    EXPECT_FALSE(fs::exists(dir / "surface" / surfaceFileName(0, "obj")));
    // summary.json of `pbf run` takes precedence over the estimate.
    std::ofstream(dir / "summary.json") << R"({"frames": 3, "particle_radius": 0.012})";
    job.range = parseFrameRange("0");
    EXPECT_EQ(meshFrames(job).radiusSource, "summary.json");
    EXPECT_FLOAT_EQ(radiusFromSummary(dir), 0.012f);
    fs::remove_all(dir);
}

TEST(MeshFrames, BadDirectoriesAndFramesAreReportedWithTheName) {
    const fs::path dir = freshDirectory("badframes");
    auto expectIoError = [](const MeshJob& job, const std::string& fragment) {
        try {
            meshFrames(job);
            FAIL() << "no error, expected " << fragment;
        } catch (const pbf::IoError& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    MeshJob job;
    job.input = dir / "missing";
    expectIoError(job, "missing: no such directory");
    job.input = dir;
    expectIoError(job, "no particle frames");
    std::ofstream(dir / "frame_00000.ply")
        << "ply\nformat binary_little_endian 1.0\nelement vertex 10\n"
           "property float x\nproperty float y\nproperty float z\nend_header\n";
    job.params.particleRadius = kR;
    expectIoError(job, "frame_00000.ply: file is shorter than its vertex count says");
    job.range = parseFrameRange("5:9");
    expectIoError(job, "none of its 1 particle frames");
    fs::remove_all(dir);
}

}  // namespace

namespace diffuse_tests {

using pbf::ParticleFrame;

// The frames of a scene as `pbf run` writes them (id order).
std::vector<ParticleFrame> simulateFrames(const std::string& json, int frames) {
    pbf::World world(pbf::parseScene(json, "scene.json"));
    std::vector<ParticleFrame> out;
    for (int k = 0; k <= frames; ++k) {
        if (k > 0) {
            EXPECT_TRUE(world.stepFrame().ok());
        }
        const pbf::ParticleStore& p = world.particles();
        ParticleFrame f;
        for (const std::uint32_t i : p.orderById()) {
            f.position.push_back(p.position.get(i));
            f.velocity.push_back(p.velocity.get(i));
            f.density.push_back(p.density[i]);
            f.id.push_back(p.id[i]);
        }
        out.push_back(std::move(f));
    }
    return out;
}

// A coarse dam break (r = 2 cm, 2,200 particles): the wave reaches the far
// wall (x = 1.6 m) at about 0.6 s and runs up it.
const std::vector<ParticleFrame>& damBreak() {
    static const std::vector<ParticleFrame> frames = simulateFrames(R"({
      "domain": {"min": [0, 0, 0], "max": [1.6, 1.0, 0.4]},
      "particle_radius": 0.02,
      "fluid": {"viscosity": 0.01},
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.5, 0.7, 0.4]}],
      "output": {"fps": 30}})",
                                                                    30);
    return frames;
}

DiffuseParams diffuseParams(float radius) {
    DiffuseParams p;
    p.particleRadius = radius;
    return p;
}

TEST(Diffuse, RestingTankMakesNoWhiteWater) {
    const std::vector<ParticleFrame> frames = simulateFrames(R"({
      "domain": {"min": [0, 0, 0], "max": [0.3, 0.4, 0.3]},
      "particle_radius": 0.01,
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.3, 0.12, 0.3]}],
      "output": {"fps": 30}})",
                                                             30);
    DiffuseSimulator sim(diffuseParams(0.01f));
    std::size_t most = 0;
    for (std::size_t k = 1; k < frames.size(); ++k) {
        sim.advance(int(k - 1), frames[k - 1], frames[k], 1.0 / 30.0);
        most = std::max(most, sim.particles().size());
    }
    EXPECT_EQ(most, 0u) << "diffuse particles in water at rest";
}

// Many diffuse particles where the wave hits the far wall, of all kinds,
// and the same bits for any thread count.
TEST(Diffuse, DamBreakImpactMakesSprayAndFoamAtTheFarWall) {
    const std::vector<ParticleFrame>& frames = damBreak();
    const auto runWith = [&](int threads) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                        std::size_t(threads));
        DiffuseSimulator sim(diffuseParams(0.02f));
        std::size_t before = 0, atImpact = 0, nearWall = 0, spray = 0, foam = 0;
        for (std::size_t k = 1; k < frames.size(); ++k) {
            sim.advance(int(k - 1), frames[k - 1], frames[k], 1.0 / 30.0);
            const DiffuseParticles& d = sim.particles();
            if (k == 12) before = d.size();  // 0.4 s: the wave is still running
            if (k >= 20 && d.size() > atImpact) {
                atImpact = d.size();
                nearWall = std::size_t(std::count_if(d.position.begin(), d.position.end(),
                                                     [](Vec3 q) { return q.x > 1.2f; }));
                spray = d.count(DiffuseType::spray);
                foam = d.count(DiffuseType::foam);
            }
        }
        std::printf(
            "dam break (%d threads): %zu diffuse at 0.4 s, up to %zu after the impact "
            "(%zu beyond x = 1.2 m; spray %zu, foam %zu)\n",
            threads, before, atImpact, nearWall, spray, foam);
        EXPECT_GT(atImpact, 200u);
        EXPECT_GT(atImpact, 2 * before);
        EXPECT_GT(nearWall, atImpact / 2);
        EXPECT_GT(spray, 0u);
        EXPECT_GT(foam, 0u);
        return sim.particles();
    };
    const DiffuseParticles one = runWith(1), two = runWith(2);
    ASSERT_EQ(one.size(), two.size());
    EXPECT_EQ(one.id, two.id);
    EXPECT_EQ(one.type, two.type);
    EXPECT_EQ(0, std::memcmp(one.position.data(), two.position.data(), one.size() * sizeof(Vec3)));
    EXPECT_EQ(0, std::memcmp(one.velocity.data(), two.velocity.data(), one.size() * sizeof(Vec3)));
}

TEST(Diffuse, FilesHoldEveryParticleWithItsType) {
    const fs::path dir = freshDirectory("diffuse");
    DiffuseParticles d;
    d.position = {{1, 2, 3}, {4, 5, 6}};
    d.velocity = {{0.5f, 0, 0}, {0, -1, 0}};
    d.type = {DiffuseType::spray, DiffuseType::bubble};
    d.lifetime = {1.5f, 2.5f};
    d.id = {7, 9};
    writeDiffusePly(dir / "diffuse_00001.ply", d);
    std::ifstream in(dir / "diffuse_00001.ply", std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t body = text.find("end_header\n") + 11;
    EXPECT_NE(text.find("element vertex 2\n"), std::string::npos);
    EXPECT_NE(text.find("property uchar type\n"), std::string::npos);
    // 6 floats, the type byte, the lifetime, the id per particle.
    ASSERT_EQ(text.size() - body, 2u * (24 + 1 + 4 + 4));
    float y = 0.0f;
    std::memcpy(&y, text.data() + body + 33 + 4, 4);
    EXPECT_EQ(y, 5.0f);
    EXPECT_EQ(std::uint8_t(text[body + 33 + 24]), 2u);  // the second one is a bubble
    writeDiffuseVdb(dir / "diffuse_00001.vdb", d);
    EXPECT_GT(fs::file_size(dir / "diffuse_00001.vdb"), 0u);
    DiffuseParams bad = diffuseParams(0.01f);
    bad.substeps = 0;
    EXPECT_NE(validate(bad).find("substeps"), std::string::npos);
    EXPECT_THROW(DiffuseSimulator{bad}, std::invalid_argument);
    fs::remove_all(dir);
}

}  // namespace diffuse_tests
