// Helpers shared by the tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"

namespace pbf::test {

// An empty directory of its own for a test (under the system's temporary
// directory, named after the test and this process).
inline std::filesystem::path freshDirectory(const std::string& name) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("pbf_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

inline std::string scenePath(const std::string& name) {
    return std::string(PBF_SCENES_DIR) + "/" + name;
}

// A small valid scene as JSON text, with `extra` spliced into the top-level object.
inline std::string smallSceneJson(const std::string& extra = "") {
    return R"({
      "name": "small",
      "domain": {"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]},
      "particle_radius": 0.02,
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}])" +
           (extra.empty() ? std::string() : ", " + extra) + "}";
}

// The backends every World runs on here (the GPU backend's source through
// cuda-on-cpu), for INSTANTIATE_TEST_SUITE_P, with their names as test-name
// suffixes (cuda_on_cpu).
inline auto everyBackendHere() {
    return ::testing::Values(BackendKind::Cpu, BackendKind::Reference, BackendKind::CudaOnCpu);
}
inline std::string backendTestName(const ::testing::TestParamInfo<BackendKind>& info) {
    std::string name(backendName(info.param));
    std::replace(name.begin(), name.end(), '-', '_');
    return name;
}

// Steps one frame; a failed frame fails the test with the world's message.
inline FrameReport stepFrame(World& world) {
    const FrameResult result = world.stepFrame();
    EXPECT_TRUE(result.ok()) << result.error->message;
    return result.report;
}

}  // namespace pbf::test
