#include "console.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pbf::cli {

ProgressBar::ProgressBar(std::string label, int total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      terminal_(::isatty(STDERR_FILENO) != 0) {}

void ProgressBar::update(int done, const std::string& detail) {
    if (!enabled_ || total_ <= 0) return;
    const double fraction = double(done) / total_;
    if (terminal_) {
        constexpr int kWidth = 30;
        const int filled = static_cast<int>(fraction * kWidth);
        fmt::print(stderr, "\r{} [{}{}] {:3.0f}% {}/{} {}\x1b[K", label_, std::string(filled, '#'),
                   std::string(kWidth - filled, '.'), 100.0 * fraction, done, total_, detail);
        std::fflush(stderr);
        return;
    }
    const int decile = static_cast<int>(fraction * 10.0);
    if (decile == lastDecile_) return;
    lastDecile_ = decile;
    fmt::print(stderr, "{} {:3.0f}% {}/{} {}\n", label_, 100.0 * fraction, done, total_, detail);
}

void ProgressBar::finish() {
    if (enabled_ && terminal_) fmt::print(stderr, "\n");
}

void printError(const std::string& message) {
    fmt::print(stderr, "pbf: error: {}\n", message);
}

std::string defaultScenePath(const std::string& fileName) {
    const std::filesystem::path local = std::filesystem::path("scenes") / fileName;
    if (std::filesystem::exists(local)) return local.string();
    return (std::filesystem::path(PBF_SCENES_DIR) / fileName).string();
}

}  // namespace pbf::cli
