// SIGINT and SIGTERM as a request to stop: the handler only sets a
// sig_atomic_t flag; the programs check it between output rows (simulate()'s
// stop predicate, a sweep's loop), finish the row, write complete outputs and
// a summary saying "interrupted", and exit with stopExitCode().
#pragma once

namespace gimbalsim::io {

/// Installs the handler for SIGINT and SIGTERM (sigaction, no SA_RESTART).
void installStopHandlers() noexcept;
/// A stop was requested (async-signal-safe read of the flag).
bool stopRequested() noexcept;
/// The signal that asked (0 if none).
int stopSignal() noexcept;
/// "SIGINT", "SIGTERM" or "signal N".
const char* stopSignalName() noexcept;
/// The documented exit code of an interrupted program: 128 + the signal (130, 143).
inline int stopExitCode() noexcept { return 128 + stopSignal(); }

}  // namespace gimbalsim::io
