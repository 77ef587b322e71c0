// Files: PLY round trip, atomic writes, the outputs of a run.
#include "pbf/io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "pbf/run.hpp"
#include "pbf/scene.hpp"
#include "support/test_util.hpp"

namespace {

namespace fs = std::filesystem;

fs::path freshDirectory(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / ("pbf_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

TEST(Ply, RoundTripKeepsEveryAttributeInIdOrder) {
    pbf::ParticleStore p;
    for (int k = 0; k < 100; ++k) {
        const float f = float(k);
        p.add({0.01f * f, 0.5f, -0.25f * f}, {f, -1.0f, 2.0f}, 1000.0f + f);
    }
    // Scramble memory order as the solver's reorder would.
    std::vector<std::uint32_t> perm(100);
    for (std::uint32_t k = 0; k < 100; ++k) perm[k] = (k * 37) % 100;
    p.reorder(perm);
    const fs::path dir = freshDirectory("ply");
    pbf::writeParticlesPly(dir / "f.ply", p);
    const pbf::ParticleFrame frame = pbf::readParticlesPly(dir / "f.ply");
    ASSERT_EQ(frame.position.size(), 100u);
    for (std::uint32_t k = 0; k < 100; ++k) {
        EXPECT_EQ(frame.id[k], k);
        const float f = float(k);
        EXPECT_EQ(frame.position[k], (pbf::Vec3{0.01f * f, 0.5f, -0.25f * f}));
        EXPECT_EQ(frame.velocity[k], (pbf::Vec3{f, -1.0f, 2.0f}));
        EXPECT_EQ(frame.density[k], 1000.0f + f);
    }
    // Header is what Blender / ParaView expect.
    std::ifstream in(dir / "f.ply", std::ios::binary);
    std::string header((std::istreambuf_iterator<char>(in)), {});
    EXPECT_NE(header.find("format binary_little_endian 1.0\n"), std::string::npos);
    EXPECT_NE(header.find("element vertex 100\n"), std::string::npos);
    EXPECT_NE(header.find("property uint id\nend_header\n"), std::string::npos);
    EXPECT_EQ(fs::file_size(dir / "f.ply"), header.find("end_header\n") + 11 + 100 * 32);
    fs::remove_all(dir);
}

TEST(Ply, TruncatedAndForeignFilesAreRejected) {
    const fs::path dir = freshDirectory("plybad");
    pbf::ParticleStore p;
    for (int k = 0; k < 10; ++k) p.add({float(k), 0, 0}, {}, 1000.0f);
    pbf::writeParticlesPly(dir / "f.ply", p);
    fs::resize_file(dir / "f.ply", fs::file_size(dir / "f.ply") - 5);
    EXPECT_THROW(pbf::readParticlesPly(dir / "f.ply"), pbf::IoError);
    std::ofstream(dir / "text.ply")
        << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n";
    EXPECT_THROW(pbf::readParticlesPly(dir / "text.ply"), pbf::IoError);
    std::ofstream(dir / "huge.ply")
        << "ply\nformat binary_little_endian 1.0\nelement vertex 999999999999\n"
           "property float x\nproperty float y\nproperty float z\nend_header\n";
    EXPECT_THROW(pbf::readParticlesPly(dir / "huge.ply"), pbf::IoError);
    EXPECT_THROW(pbf::readParticlesPly(dir / "missing.ply"), pbf::IoError);
    fs::remove_all(dir);
}

TEST(AtomicWrite, LeavesNoTemporaryAndReplacesWhole) {
    const fs::path dir = freshDirectory("atomic");
    pbf::writeFileAtomically(dir / "a.txt", [](std::ostream& out) { out << "first"; });
    pbf::writeFileAtomically(dir / "a.txt", [](std::ostream& out) { out << "second"; });
    std::ifstream in(dir / "a.txt");
    std::string text;
    in >> text;
    EXPECT_EQ(text, "second");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
    fs::remove_all(dir);
}

TEST(AtomicWrite, UnwritableDirectoryIsReported) {
    try {
        pbf::writeFileAtomically("/nonexistent_dir/x.ply", [](std::ostream& out) { out << "x"; });
        FAIL();
    } catch (const pbf::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent_dir/x.ply"), std::string::npos);
    }
}

TEST(Run, WritesFramesStatsAndSummary) {
    const fs::path dir = freshDirectory("run");
    pbf::Scene scene = pbf::parseScene(pbf::test::smallSceneJson(), "small.json");
    scene.output.directory = dir.string();
    scene.output.frames = 3;
    pbf::RunOptions options;
    int callbacks = 0;
    options.onFrame = [&](const pbf::FrameReport&) { ++callbacks; };
    const pbf::RunSummary summary = pbf::runScene(scene, options);
    EXPECT_EQ(callbacks, 4);  // the initial frame and three simulated ones
    EXPECT_EQ(summary.frames, 3);
    EXPECT_EQ(summary.particles, 125u);
    EXPECT_EQ(summary.maxEscaped, 0u);
    for (int f = 0; f <= 3; ++f) {
        const pbf::ParticleFrame frame = pbf::readParticlesPly(dir / pbf::frameFileName(f));
        EXPECT_EQ(frame.position.size(), 125u);
    }
    std::ifstream csv(dir / "stats.csv");
    std::string header, line;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("frame,time,particles,substeps,iterations,step_ms,avg_density_error,"
                           "max_density_error,kinetic_energy,escaped",
                           0),
              0u);
    int rows = 0;
    while (std::getline(csv, line)) {
        // Whole rows, one per frame, in order (the file is appended to).
        EXPECT_EQ(line.rfind(std::to_string(rows) + ",", 0), 0u) << line;
        EXPECT_EQ(std::count(line.begin(), line.end(), ','),
                  std::count(header.begin(), header.end(), ','));
        ++rows;
    }
    EXPECT_EQ(rows, 4);
    EXPECT_TRUE(fs::exists(dir / "summary.json"));
    // Nothing but the outputs: no temporaries left behind.
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
    fs::remove_all(dir);
}

TEST(Run, UnwritableOutputDirectoryIsReported) {
    pbf::Scene scene = pbf::parseScene(pbf::test::smallSceneJson(), "small.json");
    scene.output.directory = "/proc/pbf_cannot_write_here";
    scene.output.frames = 1;
    EXPECT_THROW(pbf::runScene(scene, {}), pbf::IoError);
}

}  // namespace
