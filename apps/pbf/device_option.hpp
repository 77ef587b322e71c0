// `--device` of pbf run, bench, view and render: the devices' names, and the
// check that the chosen one can run here (a clear error naming it, exit
// status 1, when it cannot: no GPU, or a build without it).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "pbf/backend/backend.hpp"

namespace pbf::cli {

// Adds --device to `command`, storing the name in `device`.
void addDeviceOption(CLI::App* command, std::string& device);
// The device named `name`; throws std::runtime_error naming it and saying
// why when it cannot run here.
BackendKind selectDevice(const std::string& name);
// `pbf --version`: the version and the devices built in.
std::string versionText();

}  // namespace pbf::cli
