// Helpers for the reliability tests (checkpoints, state guard, outputs).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "pbf/core/threading.hpp"
#include "pbf/io/scene.hpp"
#include "support/test_util.hpp"

namespace pbf::test {

inline std::filesystem::path freshTestDirectory(const std::string& name) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("pbf_rel_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::string fileBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs a test with a fixed thread count and restores the previous one.
// The reliability tests run on one thread: with a few thousand particles the
// solver's parallel loops are a handful of blocks, and on a loaded machine
// (ctest -j, other builds) libgomp's spinning workers made a 0.3 s run take
// 10 s. Thread-count independence is Determinism's job.
class ThreadCountScope {
  public:
    explicit ThreadCountScope(int threads) : saved_(threadCount()) { setThreadCount(threads); }
    ~ThreadCountScope() { setThreadCount(saved_); }
    ThreadCountScope(const ThreadCountScope&) = delete;
    ThreadCountScope& operator=(const ThreadCountScope&) = delete;

  private:
    int saved_;
};

// A dam break small enough for unit tests (about 2000 particles) that still
// splashes, so particles change cells and the memory order changes every step.
inline Scene smallDamBreak(const std::vector<SceneOverride>& extra = {}) {
    std::vector<SceneOverride> overrides = {parseOverride("particle_radius=0.02"),
                                            parseOverride("fluid.vorticity=0.05")};
    overrides.insert(overrides.end(), extra.begin(), extra.end());
    return loadScene(scenePath("dam_break.json"), overrides);
}

// `scene` with its outputs going to `dir`: `frames` frames, a checkpoint
// every `checkpointEvery` frames (none by wall-clock time).
inline Scene withOutput(Scene scene, const std::filesystem::path& dir, int frames,
                        int checkpointEvery = 3) {
    scene.output.directory = dir.string();
    scene.output.frames = frames;
    scene.output.checkpointEvery = checkpointEvery;
    scene.output.checkpointSeconds = 0.0f;
    return scene;
}

}  // namespace pbf::test
