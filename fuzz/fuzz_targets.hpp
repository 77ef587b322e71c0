// What each fuzz harness does with one input, shared by the libFuzzer
// harnesses (fuzz/fuzz_*.cpp) and the regression test that replays the
// inputs in tests/data/fuzz/ (tests/fuzz_regression_test.cpp).
//
// Every input must either be accepted or refused with the library's error
// type (SceneError, IoError); anything else (a crash, a sanitizer report, a
// different exception, a hang, unbounded memory) is a bug. Each harness
// returns the outcome: accepted, or refused with the error's message (the
// regression test checks both against tests/data/fuzz/expected.txt).
#pragma once

#include <algorithm>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pbf/io/checkpoint.hpp"
#include "pbf/io/io.hpp"
#include "pbf/io/scene.hpp"

namespace pbf::fuzz {

struct Outcome {
    bool accepted = false;
    std::string message;  // the refusal's message
};

// A scene of at most `memoryBytes` of particles (the fuzzers keep it tiny).
inline Outcome scene(std::string_view text, std::size_t memoryBytes = std::size_t{1} << 20) {
    try {
        const Scene s = parseScene(text, "fuzz.json");
        checkMemory(s, memoryBytes);  // refuses anything but tiny scenes
        const ParticleStore particles = createParticles(s);
        if (particles.size() != countParticles(s))
            throw std::logic_error("particle count mismatch");
        return {true, {}};
    } catch (const SceneError& e) {
        return {false, e.what()};
    }
}

inline constexpr const char* kOverrideBaseScene = R"({
  "name": "fuzz",
  "domain": {"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]},
  "particle_radius": 0.02,
  "solver": {"iterations": 3, "artificial_pressure": {"k": 0.1}},
  "output": {"fps": 30, "frames": 2},
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]},
                   {"min": [0.2, 0.2, 0.2], "max": [0.3, 0.3, 0.3], "velocity": [0, 1, 0]}]
})";

// Each line is one `--set` argument, applied to kOverrideBaseScene.
// Lines that are not FIELD=VALUE are skipped (as the CLI would refuse them
// one by one); the outcome is that of the scene with the others applied.
inline Outcome overrides(std::string_view text) {
    std::vector<SceneOverride> list;
    std::size_t start = 0;
    while (start <= text.size() && list.size() < 16) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        try {
            list.push_back(parseOverride(text.substr(start, end - start)));
        } catch (const SceneError&) {
        }
        start = end + 1;
    }
    try {
        const Scene s = parseScene(kOverrideBaseScene, "fuzz.json", list);
        checkMemory(s, std::size_t{1} << 20);
        createParticles(s);
        return {true, {}};
    } catch (const SceneError& e) {
        return {false, e.what()};
    }
}

inline Outcome ply(std::string_view bytes) {
    std::istringstream in{std::string(bytes), std::ios::binary};
    try {
        const ParticleFrame frame = readParticlesPly(in, "fuzz.ply");
        // 12 bytes per particle at least: never more particles than the input holds.
        if (frame.position.size() > bytes.size() / 12)
            throw std::logic_error("more particles than bytes");
        return {true, {}};
    } catch (const IoError& e) {
        return {false, e.what()};
    }
}

inline Outcome checkpoint(std::string_view bytes) {
    std::istringstream in{std::string(bytes), std::ios::binary};
    try {
        readCheckpoint(in, "fuzz.pbfck");
        return {true, {}};
    } catch (const IoError& e) {
        return {false, e.what()};
    }
}

}  // namespace pbf::fuzz
