// Terminal helpers for the CLI: progress bar, errors, memory probe.
#pragma once

#include <cstddef>
#include <string>

namespace pbf::cli {

// A one-line progress bar on stderr; redrawn in place on a terminal, printed
// every 10 % otherwise (logs, CI).
class ProgressBar {
  public:
    ProgressBar(std::string label, int total, bool enabled);
    void update(int done, const std::string& detail);
    void finish();

  private:
    std::string label_;
    int total_;
    bool enabled_;
    bool terminal_;
    int lastDecile_ = -1;
};

void printError(const std::string& message);
// Resolves a shipped scene path given relative to the source tree.
std::string defaultScenePath(const std::string& fileName);

}  // namespace pbf::cli
