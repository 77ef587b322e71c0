// Ctrl-C and SIGTERM as a polite stop request: the handler only records the
// signal; the run loop polls stopSignal() between frames, writes a checkpoint
// and exits cleanly. A second Ctrl-C kills at once (the handler resets itself).
#pragma once

namespace pbf::cli {

// Installs the handlers for SIGINT and SIGTERM.
void installStopHandlers();
// The signal received (SIGINT or SIGTERM), or 0.
int stopSignal();

}  // namespace pbf::cli
