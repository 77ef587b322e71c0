// Files: PLY round trip, atomic writes.
#include "pbf/io/io.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>

#include "pbf/io/scene.hpp"
#include "support/test_util.hpp"

namespace {

namespace fs = std::filesystem;

using pbf::test::freshDirectory;

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

std::string readWhole(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::size_t filesIn(const fs::path& dir) {
    return std::size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// A reader never sees a partial file: while the new content is being
// written, the path still holds the old content whole, and afterwards the
// new one whole. (A writer that opens the path itself and writes in place
// shows a truncated file here.)
// Ids are 64-bit; PLY has no 64-bit integer, so its `uint id` holds them
// while they fit and a frame with a larger one is refused by name, the file
// not written.
TEST(Ply, AnIdPastThirtyTwoBitsIsRefusedNamingTheFormatsThatKeepIt) {
    pbf::ParticleStore p;
    p.setNextId((std::uint64_t{1} << 32) - 1);
    p.add({0, 0, 0}, {}, 1000.0f);  // id 2^32 - 1: fits
    const fs::path dir = freshDirectory("wide_id_ply");
    pbf::writeParticlesPly(dir / "fits.ply", p);
    EXPECT_EQ(pbf::readParticlesPly(dir / "fits.ply").id.at(0), 0xFFFFFFFFu);
    p.add({1, 0, 0}, {}, 1000.0f);  // id 2^32
    try {
        pbf::writeParticlesPly(dir / "f.ply", p);
        ADD_FAILURE() << "no IoError";
    } catch (const pbf::IoError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("f.ply"), std::string::npos) << message;
        EXPECT_NE(message.find("particle id 4294967296"), std::string::npos) << message;
        EXPECT_NE(message.find("output.vtk"), std::string::npos) << message;
    }
    EXPECT_FALSE(fs::exists(dir / "f.ply"));
    fs::remove_all(dir);
}

TEST(AtomicWrite, ThePathHoldsTheOldFileWholeUntilTheNewOneIsComplete) {
    const fs::path dir = freshDirectory("atomic");
    const fs::path path = dir / "a.txt";
    pbf::writeFileAtomically(path, [](std::ostream& out) { out << "first"; });
    std::string seenDuringWrite;
    pbf::writeFileAtomically(path, [&](std::ostream& out) {
        out << "sec";
        out.flush();
        seenDuringWrite = readWhole(path);
        out << "ond";
    });
    EXPECT_EQ(seenDuringWrite, "first");
    EXPECT_EQ(readWhole(path), "second");
    EXPECT_EQ(filesIn(dir), 1u);  // no temporary left
    fs::remove_all(dir);
}

// A writer that fails half way leaves the old file as it was and nothing
// beside it, and the failure reaches the caller.
TEST(AtomicWrite, AWriterThatThrowsLeavesTheOldFileAndNoTemporary) {
    const fs::path dir = freshDirectory("atomic_throw");
    const fs::path path = dir / "a.txt";
    pbf::writeFileAtomically(path, [](std::ostream& out) { out << "first"; });
    EXPECT_THROW(pbf::writeFileAtomically(path,
                                          [](std::ostream& out) {
                                              out << "half";
                                              throw std::runtime_error("writer failed");
                                          }),
                 std::runtime_error);
    EXPECT_EQ(readWhole(path), "first");
    EXPECT_EQ(filesIn(dir), 1u);
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

}  // namespace
