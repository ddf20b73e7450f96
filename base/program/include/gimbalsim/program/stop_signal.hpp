// SIGINT, SIGTERM and SIGHUP as a request to stop: the handler only sets a lock-free
// atomic flag (readable from any thread); the programs check it between
// output rows (simulate()'s stop predicate, a sweep's loop, a bench's tick),
// finish the row, write complete outputs and a summary saying "interrupted",
// and exit with stopExitCode().
#pragma once

namespace gimbalsim::io {

/// Installs the handler for SIGINT, SIGTERM and SIGHUP (sigaction, no SA_RESTART).
/// `also`, if given, is called by the handler after the flag is set: it must
/// be async-signal-safe (e.g. a lock-free atomic store of a program's own flag).
void installStopHandlers(void (*also)() = nullptr) noexcept;
/// A stop was requested (async-signal-safe read of the flag).
bool stopRequested() noexcept;
/// The signal that asked (0 if none).
int stopSignal() noexcept;
/// "SIGINT", "SIGTERM", "SIGHUP" or "a signal".
const char* stopSignalName() noexcept;
/// The documented exit code of an interrupted program: 128 + the signal (130, 143, 129).
inline int stopExitCode() noexcept { return 128 + stopSignal(); }

}  // namespace gimbalsim::io
