// Fuzzing regressions: every input in tests/data/fuzz/<harness>/ (crashes the
// fuzzers found, see docs/reliability.md) and the seed corpus in
// fuzz/corpus/ is replayed through the same code as the libFuzzer harnesses
// (fuzz/fuzz_targets.hpp). Each file's outcome is written down in
// tests/data/fuzz/expected.txt — accepted, or refused with a message that
// names the problem — and checked: an input that starts being accepted, is
// refused for another reason, or crashes fails the test, and so does a new
// input whose outcome nobody wrote down.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>

#include "fuzz_targets.hpp"
#include "pbf/io/scene.hpp"
#include "support/reliability_util.hpp"

namespace {

namespace fs = std::filesystem;
using pbf::test::fileBytes;

const fs::path kSource = fs::path(PBF_SOURCE_DIR);

struct Expected {
    bool accepted = false;
    std::string refusal;  // a part of the refusal's message
};

// Lines "PATH | accept" or "PATH | refuse | MESSAGE PART", PATH relative to
// the source tree; '#' starts a comment line.
std::map<std::string, Expected> readExpectations() {
    std::map<std::string, Expected> table;
    std::ifstream in(kSource / "tests" / "data" / "fuzz" / "expected.txt");
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> fields;
        std::stringstream parts(line);
        std::string field;
        while (std::getline(parts, field, '|')) {
            const auto first = field.find_first_not_of(' ');
            const auto last = field.find_last_not_of(' ');
            fields.push_back(first == std::string::npos ? ""
                                                        : field.substr(first, last - first + 1));
        }
        EXPECT_GE(fields.size(), 2u) << line;
        if (fields.size() < 2) continue;
        table[fields[0]] = {fields[1] == "accept", fields.size() > 2 ? fields[2] : ""};
    }
    EXPECT_FALSE(table.empty()) << "tests/data/fuzz/expected.txt is missing";
    return table;
}

using Harness = std::function<pbf::fuzz::Outcome(std::string_view)>;

// Replays every file of `dir` (relative to the source tree); returns the count.
int replay(const std::string& dir, const Harness& harness) {
    static const std::map<std::string, Expected> expected = readExpectations();
    int files = 0;
    for (const auto& entry : fs::directory_iterator(kSource / dir)) {
        if (!entry.is_regular_file()) continue;
        ++files;
        const std::string key = dir + "/" + entry.path().filename().string();
        pbf::fuzz::Outcome outcome;
        EXPECT_NO_THROW(outcome = harness(fileBytes(entry.path()))) << key;
        const auto it = expected.find(key);
        if (it == expected.end()) {
            ADD_FAILURE() << "no expected outcome for " << key
                          << " in tests/data/fuzz/expected.txt; "
                          << "it was " << (outcome.accepted ? "accepted" : "refused: ")
                          << outcome.message;
            continue;
        }
        EXPECT_EQ(outcome.accepted, it->second.accepted) << key << ": " << outcome.message;
        if (!it->second.accepted) {
            EXPECT_NE(outcome.message.find(it->second.refusal), std::string::npos)
                << key << ": refused with \"" << outcome.message << "\", expected \""
                << it->second.refusal << "\"";
        }
    }
    return files;
}

TEST(FuzzRegression, SceneInputs) {
    EXPECT_GE(
        replay("tests/data/fuzz/scene", [](std::string_view t) { return pbf::fuzz::scene(t); }), 1);
}

// The seeds of the scene fuzzer are the shipped scenes: every one loads and
// fills its blocks (with the memory of a real machine, not the fuzzer's 1 MiB).
TEST(FuzzRegression, ShippedScenesAreAccepted) {
    int scenes = 0;
    for (const auto& entry : fs::directory_iterator(kSource / "scenes")) {
        if (entry.path().extension() != ".json") continue;
        ++scenes;
        const pbf::fuzz::Outcome outcome =
            pbf::fuzz::scene(fileBytes(entry.path()), std::size_t{8} << 30);
        EXPECT_TRUE(outcome.accepted) << entry.path() << ": " << outcome.message;
    }
    EXPECT_GE(scenes, 7);
}

TEST(FuzzRegression, OverrideInputs) {
    const auto harness = [](std::string_view t) { return pbf::fuzz::overrides(t); };
    replay("tests/data/fuzz/override", harness);
    EXPECT_EQ(replay("fuzz/corpus/override", harness), 4);
}

TEST(FuzzRegression, PlyInputs) {
    EXPECT_EQ(replay("fuzz/corpus/ply", [](std::string_view t) { return pbf::fuzz::ply(t); }), 4);
}

TEST(FuzzRegression, CheckpointInputs) {
    EXPECT_EQ(replay("fuzz/corpus/checkpoint",
                     [](std::string_view t) { return pbf::fuzz::checkpoint(t); }),
              1);
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
