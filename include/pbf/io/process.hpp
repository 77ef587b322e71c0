// Running helper programs (ffmpeg for videos, Python for plots): the one
// place that starts a process, waits for it and collects what it printed.
// Helpers are optional at run time: callers turn "not installed" into a
// message, never into an exception.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pbf {

// The full path of `program` on $PATH, if it is there and executable. A name
// with a '/' is checked as it is.
std::optional<std::filesystem::path> findProgram(const std::string& program);

struct ProgramResult {
    bool started = false;  // false: the program could not be run (see `output`)
    int exitStatus = -1;   // the exit status, or -1 when it was killed by a signal
    std::string output;    // stdout and stderr together (the last 64 KiB)
    bool ok() const { return started && exitStatus == 0; }
};

// Runs argv[0] (a path) with the arguments argv[1..] and waits for it; stdin
// is /dev/null. Never throws for a program that is missing or fails.
ProgramResult runProgram(const std::vector<std::string>& argv);

}  // namespace pbf
