#include "tick_log.hpp"

#include <cinttypes>
#include <cstdio>
#include <utility>

namespace gimbalsim::firmware {

std::string TickLog::boundsProblem(std::int64_t ticks) {
  if (ticks <= 0) return "needs a bounded run (--duration > 0): the table of ticks is reserved before the loop starts";
  if (ticks > kMaxTicks) {
    return std::to_string(ticks) + " ticks asked; it holds at most " + std::to_string(kMaxTicks) +
           " (20 bytes each, reserved at start): shorten --duration or lower --rate";
  }
  return "";
}

bool TickLog::open(const std::string& path, std::int64_t ticks, const std::vector<std::string>& inputs,
                   std::string* why) {
  if (std::string bound = boundsProblem(ticks); !bound.empty()) {  // the caller checked; never a huge table
    *why = std::move(bound);
    return false;
  }
  try {
    file_.emplace(path, inputs);
  } catch (const io::OutputError& e) {
    *why = e.what();
    return false;
  }
  rows_.reserve(static_cast<std::size_t>(ticks));
  return true;
}

bool TickLog::writeRows(std::string* why) {
  if (!file_) return true;
  // Through OutputFile::write, not fprintf: a failed write keeps its reason (a full disk, EFBIG).
  bool ok = file_->write("tick,substeps,derivatives,stepping_cpu_us,compute_cpu_us,compute_wall_us\n");
  char line[160];
  // [us] with the ns digits (the spans are >= 0): every digit measured, none made up.
  for (std::size_t k = 0; k < rows_.size() && ok; ++k) {
    const TickRecord& r = rows_[k];
    const int n = std::snprintf(line, sizeof line,
                                "%zu,%" PRId32 ",%" PRId32 ",%" PRId32 ".%03" PRId32 ",%" PRId32 ".%03" PRId32
                                ",%" PRId32 ".%03" PRId32 "\n",
                                k, r.substeps, r.derivatives, r.stepping_cpu_ns / 1000, r.stepping_cpu_ns % 1000,
                                r.compute_cpu_ns / 1000, r.compute_cpu_ns % 1000, r.compute_wall_ns / 1000,
                                r.compute_wall_ns % 1000);
    ok = file_->write({line, static_cast<std::size_t>(n)});
  }
  if (file_->ok()) return true;
  *why = file_->error().empty() ? file_->path() + ": a write failed" : file_->error();
  return false;
}

}  // namespace gimbalsim::firmware
