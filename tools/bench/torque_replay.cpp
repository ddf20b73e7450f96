// torque_replay: a stand-in controller that answers a lockstep firmware_sim
// with the torques another run applied, tick by tick, read from that run's
// truth CSV (tau1_Nm, tau2_Nm: what acted over each tick). The plant's
// dynamics then follow the recorded run bit for bit (the CSV's numbers
// round-trip exactly; the torques are already within the limits), so its
// steps do the same work at every tick: tools/hil/worst_tick.py replays a
// real-time run in lockstep to tell a real-time tick's own cost from what
// the machine added to it. Answers status k with the torque of row k + 1 (a
// command answering status k acts from tick k + 1); tick 0 ran before any
// command in both runs. A status whose time is not its row's (sim_time_s: the
// plant ticks at another control period) stops the replay, and so does a
// truth message that is not its row's bit for bit, every state column (another
// scene or --set: pass 70 found such a replay exit 0), as does a status saying the plant rejected the
// last answer (the recorded torque acted in the recorded run: a plant that refuses it is another one;
// the replay exited 6, "the plant has gone", after the plant ended the run on 30 of them). Exit 0 after
// answering the last status the CSV covers; 2 refused input, or a plant
// ticking at another period; 5 network (a failed send too); 6 no plant within --idle-exit;
// 8 not reproduced.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/lcm_wire/udpm_sender.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"
#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/program/program.hpp"
#include "truth_torques.hpp"

namespace {

using gimbalsim::program::refuse;
using gimbalsim::bench::readTorques;
using gimbalsim::bench::Torques;
/// A truth message's columns as the truth CSV names them (TruthFields' order, as firmware_sim writes them), and
/// its values.
void truthColumns(gimbalsim::gimbal_truth_t& tr, std::vector<std::string>* names, std::vector<double>* values) {
  names->clear();
  values->clear();
  gimbalsim::contract::TruthFields::visit(
      [&](gimbalsim::contract::Columns cols, const auto& x) {
        auto col = cols.begin();
        const auto put = [&](double v) {
          names->push_back(gimbalsim::io::csvNameOf(*col++));
          values->push_back(v);
        };
        if constexpr (std::is_array_v<std::remove_cvref_t<decltype(x)>>) {
          for (const auto& v : x) put(static_cast<double>(v));
        } else {
          put(static_cast<double>(x));
        }
      },
      tr);
}

/// The truth columns a replay compares: the plant's state and what it makes of it. Not the tick's clock
/// (utime_us: wall time in a real-time run) nor the status's fault flags (a real-time tick may miss its
/// command; a replay never does), and not what the replay checks otherwise or sends itself: seq and
/// sim_time_s (each status's time against its row, within the 1 us of a utime), tau1_Nm and tau2_Nm.
std::vector<std::string> comparableColumns() {
  gimbalsim::gimbal_truth_t tr{};
  std::vector<std::string> names;
  std::vector<double> values;
  truthColumns(tr, &names, &values);
  names.erase(std::remove_if(names.begin(), names.end(),
                             [](const std::string& n) {
                               return n == "utime_us" || n == "faults" || n == "seq" || n == "sim_time_s" ||
                                      n == "tau1_Nm" || n == "tau2_Nm";
                             }),
              names.end());
  return names;
}

// A truth message of the replayed plant against its row: every compared column bit for bit (the CSV's numbers
// round-trip exactly), by the row's hash; the first that differs is named from the row read again.
class TruthCheck {
 public:
  TruthCheck(const Torques& t, std::string path) : t_(t), path_(std::move(path)) {}

  void check(const gimbalsim::lcm_wire::Message& m, std::int64_t* compared, std::string* diverged) {
    gimbalsim::gimbal_truth_t tr{};
    if (tr.decode(m.data, 0, static_cast<int>(m.size)) != static_cast<int>(m.size)) return;
    if (tr.seq < 0 || static_cast<std::size_t>(tr.seq) >= t_.row_hash.size()) return;
    const auto k = static_cast<std::size_t>(tr.seq);
    truthColumns(tr, &names_, &values_);
    picked_.clear();
    for (const std::string& c : t_.compared_columns) {
      picked_.push_back(values_[static_cast<std::size_t>(std::find(names_.begin(), names_.end(), c) - names_.begin())]);
    }
    if (gimbalsim::bench::valuesHash(picked_) == t_.row_hash[k]) {
      if (matched_.empty()) matched_.assign(t_.row_hash.size(), 0);
      *compared += matched_[k] ? 0 : 1;  // a truth heard twice is one row compared
      matched_[k] = 1;
      return;
    }
    std::string column = "a column";
    double got = 0.0, want = 0.0;
    try {
      const std::vector<double> row = gimbalsim::bench::readRow(path_, k, t_.compared_columns);
      for (std::size_t i = 0; i < row.size(); ++i) {
        if (row[i] == picked_[i]) continue;
        column = t_.compared_columns[i];
        got = picked_[i];
        want = row[i];
        break;
      }
    } catch (const std::runtime_error& e) {
      column = "a column (the row could not be read again: " + std::string(e.what()) + ")";
    }
    char why[1024];  // the column, or why the row could not be read again (a path)
    std::snprintf(why, sizeof why, "truth %lld (t = %.9g s): %s %.17g where the recorded run's row has %.17g: the "
                  "replayed plant does not follow the recorded run (another scene or --set?)",
                  static_cast<long long>(tr.seq), tr.sim_time, column.c_str(), got, want);
    *diverged = why;
  }

  /// The rows no truth was compared with, as ranges ("499..500"), at most five of them named.
  std::string unmatchedRows() const {
    std::string out;
    int named = 0, more = 0;
    const auto unmatched = [&](std::size_t k) { return matched_.empty() || !matched_[k]; };
    for (std::size_t k = 0; k < t_.row_hash.size(); ++k) {
      if (!unmatched(k)) continue;
      std::size_t end = k;
      while (end + 1 < t_.row_hash.size() && unmatched(end + 1)) ++end;
      if (named++ < 5) {
        out += (named > 1 ? ", " : "") + std::to_string(k) + (end > k ? ".." + std::to_string(end) : "");
      } else {
        ++more;
      }
      k = end;
    }
    return more ? out + " and " + std::to_string(more) + " more" : out;
  }

 private:
  const Torques& t_;
  std::string path_;
  std::vector<char> matched_;  // per row: a truth of the replayed plant matched it
  std::vector<std::string> names_;
  std::vector<double> values_, picked_;
};

int mainImpl(int argc, char** argv) {
  CLI::App app{"torque_replay: answers a lockstep firmware_sim with the torques of a recorded run"};
  std::string truth, url, prefix;
  double idle_exit = 10.0;
  app.add_option("truth_csv", truth, "the recorded run's firmware_sim --truth-csv (every tick)")->required();
  app.add_option("--lcm-url", url, "LCM provider URL (udpm)")
      ->check(CLI::Validator(gimbalsim::lcm_wire::lcmUrlProblem, "URL"));
  app.add_option("--channel-prefix", prefix, "prefix of every channel name");
  app.add_option("--idle-exit", idle_exit, "wait at most this many wall seconds for a status, then exit 6")
      ->capture_default_str()->check(gimbalsim::program::within(0.1, 1e6));  // its clock read every 0.1 s at least
  if (const auto rc = gimbalsim::program::parse(app, argc, argv, "torque_replay")) return *rc;
  if (const std::string why = gimbalsim::lcm_wire::defaultLcmUrlProblem(url); !why.empty()) {
    return gimbalsim::program::refuse("torque_replay", why);
  }
  if (const std::string why = gimbalsim::contract::Channels::prefixProblem(prefix); !why.empty()) {
    return refuse("torque_replay", "--channel-prefix '" + prefix + "': " + why);
  }
  Torques t;
  try {
    t = readTorques(truth, comparableColumns());
  } catch (const std::runtime_error& e) {
    return refuse("torque_replay", e.what());
  }
  const double stop_s = t.frozen_rows > 0 ? t.t_s[t.t_s.size() - t.frozen_rows - 1] : 0.0;  // [s] last good state
  if (t.frozen_rows > 0) {  // replayed whole: a plant that reproduces the run stops where it did
    std::fprintf(stderr, "torque_replay: the recorded plant stopped after t = %.9g s, its last good state (its "
                 "last %zu rows are its frozen state): their commands are replayed, and the replayed plant must "
                 "have stopped there too\n", stop_s, t.frozen_rows);
  }
  gimbalsim::lcm_wire::UdpmSender tx;
  const auto ch = gimbalsim::contract::Channels::withPrefix(prefix);
  gimbalsim::lcm_wire::UdpmReceiver rx({}, gimbalsim::lcm_wire::ChannelFilter({ch.status, ch.truth}));
  if (std::string why; !tx.open(url, &why) || !rx.open(url, 1 << 20, &why)) {
    std::fprintf(stderr, "torque_replay: network: %s\n", why.c_str());
    return gimbalsim::program::kNetwork;
  }
  const auto last = static_cast<std::int64_t>(t.tau1.size()) - 2;  // the last status that has a next row
  std::int64_t answered = -1, seq = 0;
  std::int64_t heard_ns = gimbalsim::lcm_wire::monotonicNs();
  bool sent = true;
  std::string mismatch;  // a status at another time than its row: another control period
  std::string diverged;  // a status past the recorded stop without the plant's fault, or a truth off its row
  TruthCheck truth_check(t, truth);
  std::int64_t compared = 0;  // truths that matched their rows
  std::int64_t asked_again = 0;  // the answered status heard again: a lockstep plant awaiting status 0's answer
                                 // re-sends it (the rejection of an answer shows first in status 1's flags)
  const auto rows = static_cast<std::int64_t>(t.row_hash.size());
  // The truths compared out of the CSV's rows, the rest named (pass 105: "at 499 ticks" of 501 rows said neither;
  // pass 109: a plant that ended first said nothing of them)
  const auto say_compared = [&] {
    if (compared > 0) {
      std::fprintf(stderr, "torque_replay: the replayed plant's truth (%zu columns of its message: all but "
                   "utime_us, seq, sim_time_s, tau1_Nm, tau2_Nm and faults) matched the recorded one bit for bit at "
                   "%lld of the %lld rows%s\n", t.compared_columns.size(), static_cast<long long>(compared),
                   static_cast<long long>(rows), compared == rows ? "" : ("; no truth heard for rows " +
                   truth_check.unmatchedRows() + ": not compared (the plant ended first, or the bus lost them)")
                                                                           .c_str());
    } else {
      std::fprintf(stderr, "torque_replay: warning: no truth compared (%s): the replayed dynamics were not checked "
                   "against the recorded run\n", t.compared_columns.empty() ? "the CSV has none of the truth's "
                   "columns" : ("none heard on " + ch.truth).c_str());
    }
  };
  while (answered < last && sent && mismatch.empty() && diverged.empty()) {
    if (rx.wait(100, 0) < 0) return gimbalsim::program::kNetwork;
    rx.drain([&](const gimbalsim::lcm_wire::Message& m, std::int64_t) {
      if (!sent || !mismatch.empty() || !diverged.empty()) return;
      if (m.channel == ch.truth) {
        truth_check.check(m, &compared, &diverged);
        return;
      }
      gimbalsim::gimbal_status_t st{};
      if (st.decode(m.data, 0, static_cast<int>(m.size)) != static_cast<int>(m.size)) return;
      heard_ns = gimbalsim::lcm_wire::monotonicNs();
      if (st.seq == answered) ++asked_again;
      if (st.seq <= answered || st.seq > last) return;  // a repeat (status 0 is re-sent until answered), or past the CSV
      const auto k = static_cast<std::size_t>(st.seq);
      // Our last answer (command seq - 1) rejected: the flag, and the plant's last accepted command not it.
      if (answered >= 0 && (st.faults & gimbalsim::gimbal_status_t::FAULT_COMMAND_REJECTED) != 0 &&
          st.last_command_seq != seq - 1) {
        char why[512];
        std::snprintf(why, sizeof why, "status %lld (t = %.9g s) says the plant rejected the answer to status %lld "
                      "(row %lld's torques %.9g, %.9g N m), which acted in the recorded run: the replayed plant "
                      "refuses what the recorded one took (its torque.limit, or another controller on the bus)",
                      static_cast<long long>(st.seq), static_cast<double>(st.utime) * 1e-6,
                      static_cast<long long>(answered), static_cast<long long>(answered + 1),
                      t.tau1[static_cast<std::size_t>(answered) + 1], t.tau2[static_cast<std::size_t>(answered) + 1]);
        diverged = why;
        return;
      }
      // The replayed plant stops where the recorded one did, and only there: a row from the recorded stop on
      // (its first row carrying FAULT_PLANT_FAULT) is answered by a status carrying it, a row before by one without.
      const bool stopped = (st.faults & gimbalsim::gimbal_status_t::FAULT_PLANT_FAULT) != 0;
      const bool recorded_stop = k >= t.first_fault_row;
      if (recorded_stop != stopped) {
        char why[320];
        if (stopped) {
          std::snprintf(why, sizeof why, "status %lld (t = %.9g s) carries FAULT_PLANT_FAULT, where the recorded "
                        "plant ran on to row %lld (t = %.9g s): the replayed plant stopped where the recorded one did "
                        "not", static_cast<long long>(st.seq), static_cast<double>(st.utime) * 1e-6,
                        static_cast<long long>(st.seq), t.t_s[k]);
        } else {
          std::snprintf(why, sizeof why, "status %lld (t = %.9g s) has no FAULT_PLANT_FAULT, where the recorded "
                        "plant had stopped after t = %.9g s: the replayed plant did not stop where the recorded one "
                        "did", static_cast<long long>(st.seq), static_cast<double>(st.utime) * 1e-6, stop_s);
        }
        diverged = why;
        return;
      }
      // Lockstep's utime is simulated time, rounded to 1 us: row k's time, or the plant ticks at another period
      // (from the stop on, a row holds the frozen state's time, not its tick's).
      if (!t.t_s.empty() && !recorded_stop && std::fabs(static_cast<double>(st.utime) * 1e-6 - t.t_s[k]) > 1e-6) {
        char why[256];
        std::snprintf(why, sizeof why, "status %lld is at t = %.9g s, row %lld of the truth CSV at %.9g s: the plant "
                      "ticks at another control period than the recorded run (give firmware_sim the run's --rate)",
                      static_cast<long long>(st.seq), static_cast<double>(st.utime) * 1e-6,
                      static_cast<long long>(st.seq), t.t_s[k]);
        mismatch = why;
        return;
      }
      gimbalsim::gimbal_command_t c{};
      c.utime = st.utime;
      c.seq = seq++;
      c.status_seq = st.seq;
      c.mode = gimbalsim::gimbal_command_t::MODE_TORQUE;
      c.torque[0] = t.tau1[k + 1];
      c.torque[1] = t.tau2[k + 1];
      sent = tx.send(ch.command, c);  // a lost answer would stall the plant: stop and say so
      answered = st.seq;
      asked_again = 0;
    }, 256);
    if (static_cast<double>(gimbalsim::lcm_wire::monotonicNs() - heard_ns) * 1e-9 > idle_exit) {
      if (answered >= 0 && asked_again > 0) {  // it went on asking for the answer we gave, then went
        const auto row = static_cast<std::size_t>(answered) + 1;
        std::fprintf(stderr, "torque_replay: not reproduced: the plant asked again for the answer to status %lld "
                     "after it was sent (row %lld's torques %.9g, %.9g N m, which acted in the recorded run) and then "
                     "ended the run: it did not take them (its summary says why: a torque.limit below them, or another "
                     "controller on the bus)\n", static_cast<long long>(answered), static_cast<long long>(row),
                     t.tau1[row], t.tau2[row]);
        return gimbalsim::program::kNotReproduced;
      }
      if (answered < 0) {  // not one status heard: no plant (the pointing controller's --idle-exit words)
        std::fprintf(stderr, "torque_replay: error: no status for %g s: no plant on %s\n", idle_exit, ch.status.c_str());
      } else {
        std::fprintf(stderr, "torque_replay: error: the plant has gone: no status for %g s after status %lld\n",
                     idle_exit, static_cast<long long>(answered));
        say_compared();
      }
      return gimbalsim::program::kNoPeer;
    }
  }
  if (!mismatch.empty()) {
    std::fprintf(stderr, "torque_replay: error: %s; replay stopped\n", mismatch.c_str());
    return gimbalsim::program::kRefused;
  }
  if (!diverged.empty()) {
    std::fprintf(stderr, "torque_replay: not reproduced: %s; replay stopped\n", diverged.c_str());
    return gimbalsim::program::kNotReproduced;
  }
  if (!sent) {
    std::fprintf(stderr, "torque_replay: error: publishing the answer to status %lld failed\n",
                 static_cast<long long>(answered));
    return gimbalsim::program::kNetwork;
  }
  // (pass 105) the plant publishes the truth of its last ticks after the last answer: heard for up to 1 s more
  for (const std::int64_t until_ns = gimbalsim::lcm_wire::monotonicNs() + 1'000'000'000LL;
       compared > 0 && compared < rows && diverged.empty() && gimbalsim::lcm_wire::monotonicNs() < until_ns;) {
    if (rx.wait(100, 0) < 0) break;
    rx.drain([&](const gimbalsim::lcm_wire::Message& m, std::int64_t) {
      if (m.channel == ch.truth && diverged.empty()) truth_check.check(m, &compared, &diverged);
    }, 256);
  }
  if (!diverged.empty()) {
    std::fprintf(stderr, "torque_replay: not reproduced: %s\n", diverged.c_str());
    return gimbalsim::program::kNotReproduced;
  }
  std::fprintf(stderr, "torque_replay: answered statuses 0..%lld from %s\n", static_cast<long long>(last),
               truth.c_str());
  say_compared();
  return gimbalsim::program::kOk;
}

}  // namespace

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("torque_replay", [&] { return mainImpl(argc, argv); });
}
