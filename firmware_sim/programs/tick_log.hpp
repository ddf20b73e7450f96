// --tick-log: each tick's work and times, one CSV row per tick. The loop
// thread fills a table reserved at start (no allocation, no exception, no
// I/O in the loop); the rows are written after the run, through the same
// io::OutputFile as --truth-csv. Two lockstep runs do the same work tick by
// tick, so their logs tell the tick's work from what the machine added.
#pragma once

#include <cstdint>
#include <climits>
#include <optional>
#include <string>
#include <vector>

#include "gimbalsim/io/output_file.hpp"

namespace gimbalsim::firmware {

/// One tick, as the loop measured it.
struct TickRecord {
  std::int32_t substeps = 0;     ///< RK4 sub-steps of the tick's stepping
  std::int32_t derivatives = 0;  ///< forward-dynamics evaluations of the tick's stepping
  std::int32_t stepping_cpu_ns = 0;  ///< [ns] the stepping, loop thread CPU time
  std::int32_t compute_cpu_ns = 0;   ///< [ns] the tick's whole compute, loop thread CPU time
  std::int32_t compute_wall_ns = 0;  ///< [ns] the same span in wall time
};

/// A span [ns] as a record field: spans beyond 2.1 s are held at INT32_MAX.
constexpr std::int32_t spanField(std::int64_t ns) noexcept {
  return ns > INT32_MAX ? INT32_MAX : static_cast<std::int32_t>(ns);
}

/// The record of the tick a Firmware just ran, from the loop's spans [ns].
template <class Firmware>
TickRecord tickRecord(const Firmware& fw, std::int64_t stepping_cpu_ns, std::int64_t compute_cpu_ns,
                      std::int64_t compute_wall_ns) noexcept {
  return {fw.lastSubsteps(), static_cast<std::int32_t>(fw.lastDerivatives()), spanField(stepping_cpu_ns),
          spanField(compute_cpu_ns), spanField(compute_wall_ns)};
}

class TickLog {
 public:
  /// 2e6 ticks (33 min at 1 kHz): 40 MB of table, held from the start.
  static constexpr std::int64_t kMaxTicks = 2000000;

  /// Why a run of `ticks` cannot have a tick log ("" when it can): an
  /// unbounded run, or one longer than kMaxTicks. A refusal of the run (exit 2).
  static std::string boundsProblem(std::int64_t ticks);
  /// Creates the temporary file and reserves `ticks` rows; false with *why
  /// when boundsProblem(ticks) says why not, or the file cannot be made.
  bool open(const std::string& path, std::int64_t ticks, const std::vector<std::string>& inputs, std::string* why);
  /// Loop thread, once per tick; nothing when no file is open.
  void add(const TickRecord& r) noexcept {
    if (file_ && rows_.size() < rows_.capacity()) rows_.push_back(r);
  }
  /// Writes the rows of the ticks run (header: tick,substeps,...); false with
  /// *why. The file is then committed with the run's other outputs.
  bool writeRows(std::string* why);
  /// The open file (null when none), for the run's io::CommitGroup.
  io::OutputFile* file() noexcept { return file_ ? &*file_ : nullptr; }

 private:
  std::optional<io::OutputFile> file_;
  std::vector<TickRecord> rows_;
};

}  // namespace gimbalsim::firmware
