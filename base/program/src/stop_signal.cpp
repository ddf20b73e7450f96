#include "gimbalsim/program/stop_signal.hpp"

#include <atomic>
#include <csignal>

namespace gimbalsim::io {

namespace {
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler stores it");
void (*g_also)() = nullptr;  // set before the handler is installed

extern "C" void onStopSignal(int sig) {
  g_signal.store(sig);
  if (g_also != nullptr) g_also();
}
}  // namespace

void installStopHandlers(void (*also)()) noexcept {
  g_also = also;
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  // SIGHUP too: a closed terminal or ssh session must leave whole outputs, not hidden temporaries (pass 70).
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

bool stopRequested() noexcept { return g_signal.load(std::memory_order_relaxed) != 0; }

int stopSignal() noexcept { return g_signal.load(); }

const char* stopSignalName() noexcept {
  switch (g_signal.load()) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "a signal";
  }
}

}  // namespace gimbalsim::io
