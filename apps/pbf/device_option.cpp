#include "device_option.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <vector>

#include "pbf/core/version.hpp"

namespace pbf::cli {

void addDeviceOption(CLI::App* command, std::string& device) {
    std::vector<std::string> names;
    for (const BackendKind kind : deviceKinds()) names.emplace_back(backendName(kind));
    command
        ->add_option("--device", device,
                     "Solver: cpu (SIMD, the default), reference (scalar, slow: for checking), "
                     "cuda (NVIDIA GPU) or cuda-on-cpu (the GPU backend's code on the CPU); "
                     "pbf --version lists the devices built in")
        ->check(CLI::IsMember(names))
        ->capture_default_str();
}

BackendKind selectDevice(const std::string& name) {
    const BackendKind kind = parseBackendKind(name);
    const DeviceInfo info = deviceInfo(kind);
    if (!info.usable) throw std::runtime_error("device " + name + ": " + info.description);
    return kind;
}

std::string versionText() {
    std::string text = std::string("pbf ") + kVersion + "\ndevices:";
    for (const BackendKind kind : deviceKinds()) {
        const DeviceInfo info = deviceInfo(kind);
        text += fmt::format(
            "\n  {:<12} {}{}", backendName(kind),
            info.usable ? "" : (info.built ? "built, not usable here: " : "not built: "),
            info.description);
    }
    return text;
}

}  // namespace pbf::cli
