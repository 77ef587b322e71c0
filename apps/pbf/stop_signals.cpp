#include "stop_signals.hpp"

#include <csignal>

namespace pbf::cli {
namespace {

// Only async-signal-safe work in the handler: store to a sig_atomic_t.
volatile std::sig_atomic_t gStopSignal = 0;

extern "C" void onStopSignal(int signal) {
    gStopSignal = signal;
}

}  // namespace

void installStopHandlers() {
    struct sigaction action {};
    action.sa_handler = onStopSignal;
    sigemptyset(&action.sa_mask);
    // SA_RESETHAND: the second signal takes the default action (terminate),
    // so a run that does not stop soon enough can still be killed with Ctrl-C.
    action.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

int stopSignal() {
    return gStopSignal;
}

}  // namespace pbf::cli
