#include "gimbalsim/program/stop_signal.hpp"

#include <csignal>

namespace gimbalsim::io {

namespace {
volatile std::sig_atomic_t g_signal = 0;

extern "C" void onStopSignal(int sig) { g_signal = sig; }
}  // namespace

void installStopHandlers() noexcept {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool stopRequested() noexcept { return g_signal != 0; }

int stopSignal() noexcept { return g_signal; }

const char* stopSignalName() noexcept {
  switch (g_signal) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    default:
      return "a signal";
  }
}

}  // namespace gimbalsim::io
