// Fuzzing regressions: every input in tests/data/fuzz/<harness>/ (crashes the
// fuzzers found, see docs/reliability.md) and the seed corpus in
// fuzz/corpus/ is replayed through the same code as the libFuzzer harnesses
// (fuzz/fuzz_targets.hpp): each must be accepted or refused with the
// library's error type, never crash.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>

#include "fuzz_targets.hpp"
#include "pbf/scene.hpp"
#include "support/reliability_util.hpp"

namespace {

namespace fs = std::filesystem;
using pbf::test::fileBytes;

// Replays every file of `dir`; returns how many were accepted.
int replay(const fs::path& dir, const std::function<bool(std::string_view)>& target, int& files) {
    int accepted = 0;
    files = 0;
    if (!fs::exists(dir)) return 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (!entry.is_regular_file()) continue;
        ++files;
        bool ok = false;
        EXPECT_NO_THROW(ok = target(fileBytes(entry.path()))) << entry.path();
        accepted += ok ? 1 : 0;
    }
    return accepted;
}

const fs::path kRegressions = fs::path(PBF_SOURCE_DIR) / "tests" / "data" / "fuzz";
const fs::path kSeeds = fs::path(PBF_SOURCE_DIR) / "fuzz" / "corpus";

TEST(FuzzRegression, SceneInputs) {
    int files = 0;
    replay(kRegressions / "scene", pbf::fuzz::scene, files);
    // The seeds are the shipped scenes: all of them load (and are too big
    // for the harness's 1 MiB memory cap, which refuses them cleanly).
    replay(fs::path(PBF_SOURCE_DIR) / "scenes", pbf::fuzz::scene, files);
    EXPECT_GE(files, 4);
}

TEST(FuzzRegression, OverrideInputs) {
    int files = 0;
    replay(kRegressions / "override", pbf::fuzz::overrides, files);
    EXPECT_GE(replay(kSeeds / "override", pbf::fuzz::overrides, files), 3);
}

TEST(FuzzRegression, PlyInputs) {
    int files = 0;
    replay(kRegressions / "ply", pbf::fuzz::ply, files);
    EXPECT_EQ(replay(kSeeds / "ply", pbf::fuzz::ply, files), files);  // the seeds are valid files
}

TEST(FuzzRegression, CheckpointInputs) {
    int files = 0;
    replay(kRegressions / "checkpoint", pbf::fuzz::checkpoint, files);
    EXPECT_EQ(replay(kSeeds / "checkpoint", pbf::fuzz::checkpoint, files), files);
}

// Deep nesting overflowed the stack when an error message or the scene
// fingerprint dumped the JSON recursively (a crash, exit 139). Too large for
// a data file, so built here.
TEST(FuzzRegression, DeeplyNestedJsonIsRefused) {
    const std::string deep = std::string(1000000, '[') + std::string(1000000, ']');
    for (const std::string& field :
         {std::string("gravity"), std::string("solver\": {\"iterations")}) {
        const std::string scene =
            "{\"" + field + "\": " + deep + (field == "gravity" ? "" : "}") +
            R"(, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "particle_radius": 0.02,
                                      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}]})";
        try {
            pbf::parseScene(scene, "deep.json");
            FAIL() << "accepted";
        } catch (const pbf::SceneError& e) {
            EXPECT_NE(std::string(e.what()).find("deep.json: JSON nested deeper than 64 levels"),
                      std::string::npos)
                << std::string(e.what()).substr(0, 200);
        }
    }
    try {
        pbf::parseScene(pbf::fuzz::kOverrideBaseScene, "base.json",
                        {pbf::parseOverride("gravity=" + deep)});
        FAIL() << "accepted";
    } catch (const pbf::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("--set gravity: value nested deeper than 64 levels"),
                  std::string::npos);
    }
    std::string path = "a";
    for (int k = 0; k < 100000; ++k) path += ".a";
    EXPECT_THROW(pbf::parseScene(pbf::fuzz::kOverrideBaseScene, "base.json",
                                 {pbf::parseOverride(path + "=1")}),
                 pbf::SceneError);
}

}  // namespace
