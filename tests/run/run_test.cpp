// `pbf run`'s driver (pbf::runScene): the files a run writes, and an output
// directory it cannot write.
#include "pbf/run/run.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "pbf/io/io.hpp"
#include "pbf/io/scene.hpp"
#include "support/reliability_util.hpp"
#include "support/test_util.hpp"

namespace {

namespace fs = std::filesystem;
using pbf::test::freshTestDirectory;

TEST(Run, WritesFramesStatsAndSummary) {
    const fs::path dir = freshTestDirectory("run");
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
