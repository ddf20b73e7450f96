// The applied torques of a firmware_sim truth CSV, tick by tick: what
// torque_replay answers a lockstep plant with. Header-only so that the fuzz
// target (tests/fuzz/fuzz_truth_torques.cpp) drives the reader itself.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <istream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <sys/stat.h>

#include "gimbalsim/input/plain_decimal.hpp"

namespace gimbalsim::bench {

constexpr std::size_t kMaxRows = 2000000;      ///< firmware_sim --tick-log's limit: 33 min at 1 kHz
constexpr std::size_t kMaxLineBytes = 1 << 16;  ///< a truth row is about 1 kB
constexpr long long kPlantFault = 8;            ///< gimbal_status_t.FAULT_PLANT_FAULT: the state frozen (latched)

struct Torques {
  std::vector<double> tau1, tau2;  ///< [N m] applied over tick k (row k)
  std::vector<double> t_s;         ///< [s] tick k's simulated time (row k's sim_time_s; empty without the column)
  /// A plant that stopped repeats its frozen state, time included, with FAULT_PLANT_FAULT on every later row
  /// (firmware_sim exit 3), while its ticks and the commands they applied go on: those rows are kept with
  /// t_s NaN (no time of the plant's), so that a replay stops where the run did. How many there were.
  std::size_t frozen_rows = 0;
  /// The first row carrying FAULT_PLANT_FAULT (the tick whose step failed; SIZE_MAX: none). A step that
  /// fails inside the tick leaves the state a sub-step on, so that row's time moves on before it freezes
  /// (pass 37): the stop is this row, not the first frozen one.
  std::size_t first_fault_row = static_cast<std::size_t>(-1);
  /// The columns a replay compares the replayed plant's truth with (those of parseTorques' `comparable` the
  /// header holds, in its order), and row k's valuesHash of them: 8 bytes a row, where the values would take
  /// some 400 (pass 72: the joint state alone let a clearance run replay onto the ideal scene).
  std::vector<std::string> compared_columns;
  std::vector<std::uint64_t> row_hash;
};

/// FNV-1a over the values' bits: equal values (as a round-trip CSV cell and the message carry them) hash alike
/// (-0 as 0: the CSV writes both "0").
inline std::uint64_t valuesHash(const std::vector<double>& values) {
  std::uint64_t h = 14695981039346656037ull;
  for (double v : values) {
    if (v == 0.0) v = 0.0;
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (int b = 0; b < 8; ++b) h = (h ^ ((bits >> (8 * b)) & 0xFF)) * 1099511628211ull;
  }
  return h;
}

/// The two torque columns of a truth CSV written every tick (its seq column
/// 0, 1, 2, ...; every cell a plain finite decimal), read from `in`, with each row's hash of the `comparable`
/// columns it holds; throws std::runtime_error naming `name`, the line and the column.
inline Torques parseTorques(std::istream& in, const std::string& name, const std::vector<std::string>& comparable = {}) {
  std::string line;
  long long lines = 0;
  // The file as firmware_sim writes it, as every reader of ours takes it: an editor's byte-order mark
  // or CRLF line ends mean the file passed through something that may have changed more.
  const auto next = [&] {
    if (!std::getline(in, line)) return false;
    ++lines;
    if (line.size() > kMaxLineBytes) throw std::runtime_error(name + ": a line longer than 64 KiB (not a truth CSV)");
    if (!line.empty() && line.back() == '\r') {
      throw std::runtime_error(name + ":" + std::to_string(lines) +
                               ": ends in CR (CRLF line ends): not as firmware_sim writes a truth CSV");
    }
    // getline reached the end without a line end: a file cut while written, its last number maybe cut too
    // (pass 72: '16' cut to '1' would be replayed; plot_bench refuses the same file)
    if (in.eof()) {
      throw std::runtime_error(name + ":" + std::to_string(lines) + ": the last line has no line end (a file cut "
                               "while written?): not as firmware_sim writes a truth CSV");
    }
    return true;
  };
  if (!next()) throw std::runtime_error(name + ": empty, no header");
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) {
    throw std::runtime_error(name + ":1: starts with a byte-order mark: not as firmware_sim writes a truth CSV");
  }
  std::vector<std::string> header;
  const bool empty_last = !line.empty() && line.back() == ',';  // getline drops an empty last field
  for (std::stringstream ss(line); std::getline(ss, line, ',');) header.push_back(line);
  if (empty_last) header.emplace_back();
  int c1 = -1, c2 = -1, cs = -1, ct = -1, cf = -1, cu = -1;
  // Any column twice: not the file firmware_sim wrote (pass 53: base_x_m twice, base_y_m gone, was taken).
  // Sorted, not compared pairwise: a 64 KiB header holds tens of thousands of names.
  std::vector<std::string> sorted = header;
  std::sort(sorted.begin(), sorted.end());
  if (const auto twice = std::adjacent_find(sorted.begin(), sorted.end()); twice != sorted.end()) {
    throw std::runtime_error(name + ":1: column " + *twice + " appears twice");
  }
  for (int j = 0; j < static_cast<int>(header.size()); ++j) {
    for (auto [column, at] : {std::pair{"tau1_Nm", &c1}, {"tau2_Nm", &c2}, {"seq", &cs}, {"sim_time_s", &ct},
                              {"faults", &cf}, {"utime_us", &cu}}) {
      if (header[j] == column) *at = j;
    }
  }
  if (c1 < 0 || c2 < 0 || cs < 0) {
    throw std::runtime_error(name + ":1: no seq, tau1_Nm and tau2_Nm columns (not a firmware_sim truth CSV)");
  }
  Torques t;
  std::vector<int> cq;  // the compared columns
  for (int j = 0; j < static_cast<int>(header.size()); ++j) {
    if (std::find(comparable.begin(), comparable.end(), header[j]) == comparable.end()) continue;
    cq.push_back(j);
    t.compared_columns.push_back(header[j]);
  }
  std::vector<double> compared;
  double t_prev = -HUGE_VAL;  // [s] the previous row's sim_time_s (when the CSV has the column)
  double utime_prev = -HUGE_VAL;  // [us] the previous row's utime_us (when the CSV has the column)
  // A cell as the writer writes it: a plain finite decimal, nothing lost to underflow (1e-400 read as 0).
  const auto number = [&](const std::vector<std::string>& f, int c, long long n) {
    double x = 0.0;
    const DecimalProblem p = c < static_cast<int>(f.size()) ? readPlainDecimal(f[c], x) : DecimalProblem::Empty;
    if (p == DecimalProblem::None && hasLeadingZero(f[c])) {  // (pass 121) 010: no writer writes one
      throw std::runtime_error(name + ":" + std::to_string(n) + ": column " + header[c] + ": '" + f[c] +
                               "' has a leading zero: not a number as the CSV writer writes it");
    }
    if (p != DecimalProblem::None) {
      throw std::runtime_error(name + ":" + std::to_string(n) + ": column " + header[c] + ": not a finite number" +
                               (p == DecimalProblem::Underflow ? " (it underflows a double)" : ""));
    }
    return x;
  };
  std::size_t rows = 0;  // data rows read: row k is tick k
  long long first_fault_line = 0;  // the line of the first row carrying FAULT_PLANT_FAULT (0: none yet)
  for (long long n = 2; next(); ++n, ++rows) {
    if (rows >= kMaxRows) throw std::runtime_error(name + ": more than 2000000 rows");
    // Every row has the header's fields (counted by commas: getline drops an empty last one).
    const std::size_t fields = static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1;
    if (fields != header.size()) {
      throw std::runtime_error(name + ":" + std::to_string(n) + ": " + std::to_string(fields) + " fields, the header has " +
                               std::to_string(header.size()));
    }
    std::vector<std::string> f;
    for (std::stringstream ss(line); std::getline(ss, line, ',');) f.push_back(line);
    const auto has = [&](int c) { return c < static_cast<int>(f.size()); };
    // Row k must be tick k: a CSV written every N ticks (--truth-every N) would replay tick N (k + 1) as tick k + 1.
    const std::string expected = std::to_string(rows);
    // a leading zero is no seq firmware_sim writes ('02' read as "not written every tick", pass 37)
    if (has(cs) && (f[cs].empty() || f[cs].find_first_not_of("0123456789") != std::string::npos ||
                    (f[cs].size() > 1 && f[cs][0] == '0'))) {
      throw std::runtime_error(name + ":" + std::to_string(n) + ": seq '" + f[cs] + "' is not a tick number");
    }
    if (!has(cs) || f[cs] != expected) {
      throw std::runtime_error(name + ":" + std::to_string(n) + ": seq " + (has(cs) ? f[cs] : "missing") +
                               " where tick " + expected +
                               " belongs: the CSV was not written every tick (firmware_sim --truth-every 1)");
    }
    // Ticks in time order: an edited or spliced file whose seq still counts is no run the plant made.
    // Every cell, read or not, is the writer's number: a row with a word or a NaN anywhere is no tick the plant made.
    for (int c = 0; c < static_cast<int>(header.size()); ++c) number(f, c, n);
    // The status's fault flags, a set of bits (as plot_bench reads them): a whole number in [0, 2^31).
    const double faults = cf >= 0 ? number(f, cf, n) : 0.0;
    if (!(faults >= 0.0 && faults < 2147483648.0 && faults == std::floor(faults))) {
      throw std::runtime_error(name + ":" + std::to_string(n) + ": column faults: " + f[cf] +
                               " is not a set of fault bits");
    }
    // The tick's utime: simulated time in lockstep, the tick's deadline on the wall clock in real time; a
    // whole number of microseconds that grows every tick either way, frozen rows included (the ticks go on).
    if (cu >= 0) {
      const double utime_us = number(f, cu, n);
      // (pass 53) in [0, 2^53]: a whole double, and far beyond any clock's (1e23 was taken as a last row)
      if (!(utime_us >= 0.0 && utime_us <= 9007199254740992.0 && utime_us == std::floor(utime_us))) {
        throw std::runtime_error(name + ":" + std::to_string(n) + ": column utime_us: " + f[cu] +
                                 " is not a whole number of microseconds in [0, 2^53]: not a time firmware_sim writes");
      }
      if (!(utime_us > utime_prev)) {
        throw std::runtime_error(name + ":" + std::to_string(n) + ": column utime_us: " + f[cu] +
                                 " is not after the previous row's: not one run's ticks in order");
      }
      utime_prev = utime_us;
    }
    if (!cq.empty()) {
      compared.clear();
      for (const int c : cq) compared.push_back(number(f, c, n));
      t.row_hash.push_back(valuesHash(compared));
    }
    const bool faulted = (static_cast<long long>(faults) & kPlantFault) != 0;
    const bool after_stop = t.first_fault_row != static_cast<std::size_t>(-1);  // a row after the stop's own
    // The stop is latched: every later row carries it, its time standing still (pass 66: a flag on one row
    // before the run's stop was taken for the stop, and the faithful replay called "not reproduced").
    if (after_stop && !faulted) {
      throw std::runtime_error(name + ":" + std::to_string(n) + ": column faults: " + f[cf] + " lacks " +
                               "FAULT_PLANT_FAULT (8), latched from line " + std::to_string(first_fault_line) +
                               " on: not one run's ticks");
    }
    if (faulted && !after_stop) {
      t.first_fault_row = t.tau1.size();
      first_fault_line = n;
    }
    if (ct >= 0) {
      const double t_s = number(f, ct, n);
      // The frozen state of a plant that stopped: its time stands still and the fault is latched from then on.
      const bool frozen = t_s == t_prev && (static_cast<long long>(faults) & kPlantFault) != 0;
      if (frozen && (t.frozen_rows > 0 || !t.tau1.empty())) {
        ++t.frozen_rows;
        t.t_s.push_back(std::nan(""));
        t.tau1.push_back(number(f, c1, n));
        t.tau2.push_back(number(f, c2, n));
        continue;
      }
      if (!(t_s > t_prev) || t.frozen_rows > 0 || after_stop) {
        throw std::runtime_error(name + ":" + std::to_string(n) + ": sim_time_s " + f[ct] +
                                 (t.frozen_rows > 0 ? " after the plant's stop (frozen rows before it)"
                                  : after_stop ? " moves on after the plant's stop (line " +
                                                     std::to_string(first_fault_line) + ")"
                                               : " is not after the previous row's") +
                                 ": not one run's ticks in order");
      }
      // Tick k is at t_0 + k T (T from the first two rows), as the plant steps; a row carrying the stop may sit a
      // sub-step on. Checked within the 1 us the replay compares statuses to (pass 51: an uneven row was found
      // only when the plant reached it, blamed on its rate).
      const double tick_s = t.t_s.size() >= 2 ? t.t_s[1] - t.t_s[0] : 0.0;
      if (tick_s > 0.0 && (static_cast<long long>(faults) & kPlantFault) == 0 &&
          std::fabs(t_s - (t.t_s[0] + static_cast<double>(rows) * tick_s)) > 1e-6) {
        char step[32];
        std::snprintf(step, sizeof step, "%.9g", tick_s);
        throw std::runtime_error(name + ":" + std::to_string(n) + ": column sim_time_s: " + f[ct] + " is not tick " +
                                 std::to_string(rows) + "'s time (the first rows step " + step +
                                 " s): not one run's ticks, each a control period on");
      }
      t_prev = t_s;
      t.t_s.push_back(t_s);
    }
    t.tau1.push_back(number(f, c1, n));
    t.tau2.push_back(number(f, c2, n));
  }
  if (t.tau1.size() < 2) throw std::runtime_error(name + ": fewer than 2 rows: nothing to replay");
  return t;
}

/// Row k's values of `columns` (a mismatch named after the fact: the rows keep only their hashes); throws
/// std::runtime_error when the file no longer holds them.
inline std::vector<double> readRow(const std::string& path, std::size_t k, const std::vector<std::string>& columns) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header, fields;
  const auto split = [&line](std::vector<std::string>& out) {
    out.clear();
    for (std::stringstream ss(line); std::getline(ss, line, ',');) out.push_back(line);
  };
  if (!std::getline(in, line)) throw std::runtime_error(path + ": no header");
  split(header);
  for (std::size_t n = 0; n <= k; ++n) {
    if (!std::getline(in, line)) throw std::runtime_error(path + ": no row " + std::to_string(k));
  }
  split(fields);
  std::vector<double> out;
  for (const std::string& c : columns) {
    const auto j = static_cast<std::size_t>(std::find(header.begin(), header.end(), c) - header.begin());
    double x = 0.0;
    if (j >= fields.size() || readPlainDecimal(fields[j], x) != DecimalProblem::None) {
      throw std::runtime_error(path + ": row " + std::to_string(k) + " has no number in column " + c);
    }
    out.push_back(x);
  }
  return out;
}

/// parseTorques of the file at path. A pipe would block and a device
/// (/dev/zero) never end: anything but a regular file is refused unopened.
inline Torques readTorques(const std::string& path, const std::vector<std::string>& comparable = {}) {
  // Said as the other readers say it (base/input readFile): the path, what it is, the system's reason.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(path + ": cannot open truth CSV: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) {
    throw std::runtime_error(path + ": not a regular file (a pipe, a device or a folder): give the truth CSV's file");
  }
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open truth CSV: " + std::strerror(errno));
  return parseTorques(in, path, comparable);
}

}  // namespace gimbalsim::bench
