// Output failures: unwritable directories and full disks are reported with
// the path, and what was written before stays whole.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "pbf/io/io.hpp"
#include "pbf/run/run.hpp"
#include "support/reliability_util.hpp"

namespace {

namespace fs = std::filesystem;
using pbf::test::freshTestDirectory;

pbf::Scene smallScene() {
    return pbf::parseScene(pbf::test::smallSceneJson(), "small.json");
}

// Runs the small scene into `dir` for `frames` frames; returns the IoError's message.
std::string runError(const fs::path& dir, int frames, const pbf::RunOptions& options = {}) {
    try {
        pbf::runScene(pbf::test::withOutput(smallScene(), dir, frames), options);
    } catch (const pbf::IoError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no IoError";
    return {};
}

TEST(OutputFailure, OutputPathBlockedByAFileIsReported) {
    const fs::path dir = freshTestDirectory("blocked");
    std::ofstream(dir / "file") << "x";
    const std::string message = runError(dir / "file" / "out", 1);
    EXPECT_NE(message.find((dir / "file" / "out").string()), std::string::npos) << message;
    EXPECT_NE(message.find("cannot create output directory"), std::string::npos) << message;
    fs::remove_all(dir);
}

// The free-space check compares fs::space with what the next frame needs
// plus the reserve; a reserve larger than any disk makes every disk "full".
TEST(OutputFailure, FullDiskIsReportedBeforeWriting) {
    const fs::path dir = freshTestDirectory("full");
    pbf::RunOptions options;
    options.reserveBytes = std::numeric_limits<std::uintmax_t>::max() / 2;
    const std::string message = runError(dir, 2, options);
    EXPECT_NE(message.find("output disk full"), std::string::npos) << message;
    EXPECT_NE(message.find(dir.string()), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(dir / pbf::frameFileName(0)));
    fs::remove_all(dir);
}

// The output directory disappears in the middle of a run (a full or removed
// volume looks the same to the writer): the next write is reported.
TEST(OutputFailure, DirectoryRemovedDuringTheRunIsReported) {
    const fs::path dir = freshTestDirectory("vanish");
    pbf::RunOptions options;
    options.onFrame = [&](const pbf::FrameReport& r) {
        if (r.frame == 1) fs::remove_all(dir / "out");
    };
    const std::string message = runError(dir / "out", 4, options);
    EXPECT_NE(message.find((dir / "out").string()), std::string::npos) << message;
    fs::remove_all(dir);
}

}  // namespace
