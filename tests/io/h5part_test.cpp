// H5Part files written and read back by one process (HDF5's serial driver,
// no MPI); the MPI ranks' collective writes are tested by
// tests/io/h5part_mpi_test.cpp under mpirun (ctest mpi.h5part_ranks).
#include "pbf/io/h5part.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/test_util.hpp"

namespace {

namespace fs = std::filesystem;

using pbf::test::freshDirectory;

std::vector<std::string> filesIn(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir))
        names.push_back(entry.path().filename().string());
    return names;
}

// 100 particles in a scrambled memory order (as after the solver's
// reorder), ids past 2^32 (the file keeps 64 bits).
pbf::ParticleStore someParticles(int n) {
    pbf::ParticleStore p;
    for (int k = 0; k < n; ++k) {
        const float f = float(k);
        p.add({0.01f * f, 0.5f, -0.25f * f}, {f, -1.0f, 2.0f + f}, 1000.0f + f);
    }
    std::vector<std::uint32_t> perm(static_cast<std::size_t>(n));
    for (std::uint32_t k = 0; k < std::uint32_t(n); ++k) perm[k] = (k * 37) % std::uint32_t(n);
    p.reorder(perm);
    for (auto& id : p.id) id += 5'000'000'000ull;
    return p;
}

TEST(H5Part, RoundTripKeepsEveryFieldTheFrameTimeAndIdsInStoreOrder) {
    if (!pbf::h5partBuilt()) GTEST_SKIP() << "pbf was built without parallel HDF5 (PBF_HDF5)";
    const pbf::ParticleStore p = someParticles(100);
    const fs::path dir = freshDirectory("h5part");
    const fs::path file = dir / "frame_00012.h5part";
    pbf::writeH5PartFile(file, 12, 0.4, p, 0, p.size(), pbf::H5PartComm::thisProcess());
    const pbf::H5PartFrame frame = pbf::readH5PartFile(file);
    EXPECT_EQ(frame.frame, 12);
    ASSERT_TRUE(frame.time.has_value());
    EXPECT_EQ(*frame.time, 0.4);
    const pbf::ParticleFrame& f = frame.particles;
    ASSERT_EQ(f.position.size(), 100u);
    ASSERT_EQ(f.velocity.size(), 100u);
    ASSERT_EQ(f.density.size(), 100u);
    ASSERT_EQ(f.id.size(), 100u);
    for (std::size_t i = 0; i < 100; ++i) {
        EXPECT_EQ(f.position[i], p.position.get(i));
        EXPECT_EQ(f.velocity[i], p.velocity.get(i));
        EXPECT_EQ(f.density[i], p.density[i]);
        EXPECT_EQ(f.id[i], p.id[i]);
    }
    EXPECT_EQ(filesIn(dir), std::vector<std::string>{"frame_00012.h5part"});
    fs::remove_all(dir);
}

TEST(H5Part, RewritingReplacesTheWholeFile) {
    if (!pbf::h5partBuilt()) GTEST_SKIP() << "pbf was built without parallel HDF5 (PBF_HDF5)";
    const fs::path dir = freshDirectory("h5part_rewrite");
    const fs::path file = dir / "frame_00001.h5part";
    const pbf::ParticleStore many = someParticles(50), few = someParticles(3);
    pbf::writeH5PartFile(file, 1, 0.1, many, 0, many.size(), pbf::H5PartComm::thisProcess());
    pbf::writeH5PartFile(file, 2, 0.2, few, 0, few.size(), pbf::H5PartComm::thisProcess());
    const pbf::H5PartFrame frame = pbf::readH5PartFile(file);
    EXPECT_EQ(frame.frame, 2);
    EXPECT_EQ(frame.time, 0.2);
    EXPECT_EQ(frame.particles.position.size(), 3u);
    EXPECT_EQ(filesIn(dir), std::vector<std::string>{"frame_00001.h5part"});
    fs::remove_all(dir);
}

TEST(H5Part, NoParticlesIsAStepOfEmptyDatasets) {
    if (!pbf::h5partBuilt()) GTEST_SKIP() << "pbf was built without parallel HDF5 (PBF_HDF5)";
    const fs::path dir = freshDirectory("h5part_empty");
    pbf::writeH5PartFile(dir / "f.h5part", 0, 0.0, pbf::ParticleStore(), 0, 0,
                         pbf::H5PartComm::thisProcess());
    const pbf::H5PartFrame frame = pbf::readH5PartFile(dir / "f.h5part");
    EXPECT_EQ(frame.frame, 0);
    EXPECT_EQ(frame.time, 0.0);
    EXPECT_TRUE(frame.particles.position.empty());
    fs::remove_all(dir);
}

TEST(H5Part, MissingDirectoryIsAnIoErrorNamingTheFileAndLeavesNothing) {
    if (!pbf::h5partBuilt()) GTEST_SKIP() << "pbf was built without parallel HDF5 (PBF_HDF5)";
    const fs::path dir = freshDirectory("h5part_missing");
    const fs::path file = dir / "no_such_directory" / "frame_00003.h5part";
    const pbf::ParticleStore p = someParticles(10);
    try {
        pbf::writeH5PartFile(file, 3, 0.1, p, 0, p.size(), pbf::H5PartComm::thisProcess());
        FAIL() << "no error for a missing directory";
    } catch (const pbf::IoError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(file.string() + ": cannot create file", 0), 0u) << message;
        EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
    }
    EXPECT_TRUE(filesIn(dir).empty());
    fs::remove_all(dir);
}

TEST(H5Part, FailedRenameLeavesNoTemporaryFile) {
    if (!pbf::h5partBuilt()) GTEST_SKIP() << "pbf was built without parallel HDF5 (PBF_HDF5)";
    // A directory where the file goes: written whole, then the rename fails.
    const fs::path dir = freshDirectory("h5part_rename");
    fs::create_directory(dir / "f.h5part");
    std::ofstream(dir / "f.h5part" / "keep") << "x";
    const pbf::ParticleStore p = someParticles(10);
    try {
        pbf::writeH5PartFile(dir / "f.h5part", 0, 0.0, p, 0, p.size(),
                             pbf::H5PartComm::thisProcess());
        FAIL() << "no error when a directory is in the file's place";
    } catch (const pbf::IoError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(
                      (dir / "f.h5part").string() + ": cannot rename temporary file into place", 0),
                  0u)
            << e.what();
    }
    EXPECT_EQ(filesIn(dir), std::vector<std::string>{"f.h5part"});
    fs::remove_all(dir);
}

TEST(H5Part, PartsThatDoNotTileTheStepAreRefused) {
    if (!pbf::h5partBuilt()) GTEST_SKIP() << "pbf was built without parallel HDF5 (PBF_HDF5)";
    const fs::path dir = freshDirectory("h5part_tile");
    const pbf::ParticleStore p = someParticles(10);
    const auto one = pbf::H5PartComm::thisProcess();
    EXPECT_THROW(pbf::writeH5PartFile(dir / "f.h5part", 0, 0.0, p, 1, 11, one),
                 std::invalid_argument);
    EXPECT_THROW(pbf::writeH5PartFile(dir / "f.h5part", 0, 0.0, p, 0, 12, one),
                 std::invalid_argument);
    EXPECT_TRUE(filesIn(dir).empty());
    fs::remove_all(dir);
}

TEST(H5Part, ReadingAFileThatIsNotHdf5NamesIt) {
    if (!pbf::h5partBuilt()) GTEST_SKIP() << "pbf was built without parallel HDF5 (PBF_HDF5)";
    const fs::path dir = freshDirectory("h5part_not_hdf5");
    std::ofstream(dir / "f.h5part") << "not hdf5\n";
    try {
        pbf::readH5PartFile(dir / "f.h5part");
        FAIL() << "no error for a text file";
    } catch (const pbf::IoError& e) {
        EXPECT_EQ(std::string(e.what()).rfind((dir / "f.h5part").string() + ": cannot open", 0), 0u)
            << e.what();
    }
    EXPECT_THROW(pbf::readH5PartFile(dir / "missing.h5part"), pbf::IoError);
    fs::remove_all(dir);
}

TEST(H5Part, IndexLinksTheFramesInOrder) {
    if (!pbf::h5partBuilt()) GTEST_SKIP() << "pbf was built without parallel HDF5 (PBF_HDF5)";
    const fs::path dir = freshDirectory("h5part_index");
    const pbf::ParticleStore first = someParticles(4), second = someParticles(7);
    const auto one = pbf::H5PartComm::thisProcess();
    pbf::writeH5PartFile(dir / "frame_00000.h5part", 0, 0.0, first, 0, first.size(), one);
    pbf::writeH5PartFile(dir / "frame_00001.h5part", 1, 0.5, second, 0, second.size(), one);
    const std::vector<fs::path> frames{"frame_00001.h5part", "frame_00000.h5part"};
    pbf::writeH5PartIndex(dir / "particles.h5part", frames);
    // Step#0 is the first frame listed, found from the index's directory.
    const pbf::H5PartFrame frame = pbf::readH5PartFile(dir / "particles.h5part");
    EXPECT_EQ(frame.frame, 1);
    EXPECT_EQ(frame.time, 0.5);
    EXPECT_EQ(frame.particles.position.size(), 7u);
    // Links, not copies (64 kB for 1,000 frames).
    EXPECT_LT(fs::file_size(dir / "particles.h5part"), 4096u);
    EXPECT_EQ(filesIn(dir).size(), 3u);
    EXPECT_THROW(pbf::writeH5PartIndex(dir / "missing" / "particles.h5part", frames), pbf::IoError);
    EXPECT_EQ(filesIn(dir).size(), 3u);
    fs::remove_all(dir);
}

TEST(H5Part, BuildWithoutHdf5SaysWhatToInstall) {
    if (pbf::h5partBuilt()) GTEST_SKIP() << "this build has parallel HDF5";
    try {
        pbf::writeH5PartFile("f.h5part", 0, 0.0, pbf::ParticleStore(), 0, 0,
                             pbf::H5PartComm::thisProcess());
        FAIL() << "no error";
    } catch (const pbf::IoError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "f.h5part: pbf was built without parallel HDF5; install libhdf5-openmpi-dev "
                  "and reconfigure");
    }
    EXPECT_THROW(pbf::writeH5PartIndex("i.h5part", {}), pbf::IoError);
    EXPECT_THROW(pbf::readH5PartFile("f.h5part"), pbf::IoError);
}

}  // namespace
