// gimbalsim_log2csv: an lcm-logger log of a gimbal bench -> one CSV per
// channel, in the format of firmware_sim --truth-csv (csv_rows.hpp: header
// names `name_unit`, round-trip numbers), so a truth CSV converted from a log is byte for byte
// the one firmware_sim writes itself. Channels are recognised by name: an
// optional UPPER_SNAKE prefix followed by GIMBAL_TRUTH, GIMBAL_STATUS,
// GIMBAL_COMMAND, GIMBAL_LOOP_STATS or GIMBAL_ATTITUDE (channels.hpp). Usage:
// --help, and docs/bench.md "Recording and reading logs".
// The log is read with our validating reader (lcm_wire/lcm_log.hpp), never
// LCM's, which trusts the lengths in an event header: a malformed log is
// refused (exit 2) with the byte offset of the bad event, before any output is
// written; a log cut inside its last event (a killed logger) is converted up
// to its last whole event, the cut reported, exit 7 (program.hpp kPartial).
// Outputs are io::OutputFile: temporary + rename, checked
// writes, never through a link or over the log.
#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gimbalsim/lcm_wire/lcm_log.hpp"
#include "gimbalsim/program/program.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/firmware_sim/csv_rows.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/gimbal_antenna_t.hpp"
#include "gimbalsim/gimbal_attitude_t.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_loop_stats_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"

namespace gimbalsim::firmware {
using namespace gimbalsim::contract;  // NOLINT: the message field lists
namespace {

namespace fs = std::filesystem;

enum class Type { Unknown, Truth, Status, Command, LoopStats, Attitude, Antenna };

struct TypeInfo {
  Type type;
  const char* name;     ///< --type spelling
  const char* channel;  ///< base channel name
};
constexpr TypeInfo kTypes[] = {
    {Type::Truth, "truth", Channels::kTruth},
    {Type::Status, "status", Channels::kStatus},
    {Type::Command, "command", Channels::kCommand},
    {Type::LoopStats, "loop_stats", Channels::kLoopStats},
    {Type::Attitude, "attitude", Channels::kAttitude},
    {Type::Antenna, "antenna", Channels::kAntenna},
};

/// The type a channel name carries: <prefix><base name>, prefix UPPER_SNAKE.
Type typeOfChannel(const std::string& ch, std::string* prefix = nullptr) {
  for (const TypeInfo& t : kTypes) {
    const std::string base = t.channel;
    if (ch.size() >= base.size() && ch.compare(ch.size() - base.size(), base.size(), base) == 0) {
      const std::string p = ch.substr(0, ch.size() - base.size());
      if (!Channels::validPrefix(p)) continue;
      if (prefix) *prefix = p;
      return t.type;
    }
  }
  return Type::Unknown;
}

const char* typeName(Type t) {
  for (const TypeInfo& i : kTypes) {
    if (i.type == t) return i.name;
  }
  return "unknown";
}

int refuse(const std::string& what) { return program::refuse("gimbalsim_log2csv", what); }

/// One output CSV: decodes the channel's messages with type M and writes rows.
class Sink {
 public:
  Sink(Type t, std::FILE* f, bool log_time) : type_(t), f_(f), log_time_(log_time) {
    // f: an OutputFile's stream; its owner checks and commits it.
    if (log_time_) std::fputs("log_utime_us,", f_);
    switch (type_) {
      case Type::Truth: std::fputs(csv::header<TruthFields>().c_str(), f_); break;
      case Type::Status: std::fputs(csv::header<StatusFields>().c_str(), f_); break;
      case Type::Command: std::fputs(csv::header<CommandFields>().c_str(), f_); break;
      case Type::LoopStats: std::fputs(csv::header<LoopStatsFields>().c_str(), f_); break;
      case Type::Attitude: std::fputs(csv::header<AttitudeFields>().c_str(), f_); break;
      case Type::Antenna: std::fputs(csv::header<AntennaFields>().c_str(), f_); break;
      case Type::Unknown: break;
    }
  }
  Sink(const Sink&) = delete;
  Sink& operator=(const Sink&) = delete;

  void add(const lcm_wire::LogEvent& e) {
    switch (type_) {
      case Type::Truth: row<gimbal_truth_t, TruthFields>(e); break;
      case Type::Status: row<gimbal_status_t, StatusFields>(e); break;
      case Type::Command: row<gimbal_command_t, CommandFields>(e); break;
      case Type::LoopStats: row<gimbal_loop_stats_t, LoopStatsFields>(e); break;
      case Type::Attitude: row<gimbal_attitude_t, AttitudeFields>(e); break;
      case Type::Antenna: row<gimbal_antenna_t, AntennaFields>(e); break;
      case Type::Unknown: break;
    }
  }
  long long rows = 0, undecodable = 0, non_finite = 0;

 private:
  /// Decodes the event as M and writes it with the field list D.
  template <class M, class D>
  void row(const lcm_wire::LogEvent& e) {
    M m;
    if (e.size > (1u << 20)) {  // far beyond any bench message: not one (and an int below)
      ++undecodable;
      return;
    }
    const int size = static_cast<int>(e.size);
    const int n = m.decode(e.data, 0, size);
    if (n < 0 || n != size) {  // garbage, another type (fingerprint) or trailing bytes
      ++undecodable;
      return;
    }
    if (!csv::allFinite<D>(m)) {  // no CSV cell holds it, and no program of the bench sends it
      ++non_finite;
      return;
    }
    if (log_time_) std::fprintf(f_, "%lld,", static_cast<long long>(e.timestamp));
    csv::writeRow<D>(f_, m);
    ++rows;
  }
  Type type_;
  std::FILE* f_;
  bool log_time_;
};

int mainImpl(int argc, char** argv) {
  std::string log_path, out_dir, out_file, prefix, type_name;
  std::vector<std::string> channels;
  bool prefix_given = false, log_time = false, list = false;
  CLI::App app{
      "gimbalsim_log2csv: lcm-logger log of a gimbal bench -> one CSV per channel (the format of firmware_sim "
      "--truth-csv: the CSV convention of docs/usage.md). Recognised channels: [PREFIX]GIMBAL_TRUTH, GIMBAL_STATUS, "
      "GIMBAL_COMMAND, GIMBAL_LOOP_STATS, GIMBAL_ATTITUDE, GIMBAL_ANTENNA."};
  app.add_option("log", log_path, "the log file (lcm-logger --lcm-url=... FILE)")->required();
  app.add_option("--out-dir", out_dir, "write <out-dir>/<log stem>_<CHANNEL>.csv (default: the log's directory)");
  app.add_option("--out", out_file, "write the one selected channel to this file");
  app.add_option("--channel", channels, "convert only this channel (repeatable)");
  app.add_option("--channel-prefix", prefix, "convert only the channels of this bench prefix, e.g. BENCH2_");
  app.add_option("--type", type_name, "decode the --channel(s) as this type: truth, status, command, loop_stats, "
                                      "attitude, antenna "
                                      "(default: from the channel name)");
  app.add_flag("--log-time", log_time, "first column log_utime_us: when the logger received the message");
  app.add_flag("--list", list, "list the channels in the log with message counts and types, then exit");
  if (const auto rc = program::parse(app, argc, argv, "gimbalsim_log2csv")) return *rc;
  prefix_given = app.count("--channel-prefix") > 0;
  // (pass 119) flags the chosen mode never reads were taken without a word (--list --out /proc/x.csv: exit 0)
  for (const char* f : {"--out", "--out-dir", "--log-time", "--channel", "--channel-prefix", "--type"}) {
    if (list && app.count(f) > 0) return refuse(std::string(f) + ": --list prints every channel and writes nothing");
  }
  if (app.count("--out") > 0 && app.count("--out-dir") > 0) {
    return refuse("--out and --out-dir: give one (--out names the one channel's file, --out-dir the folder of each)");
  }
  // (pass 78) a channel named twice was converted once: a value twice in a list flag is refused, as elsewhere
  if (const std::string why = program::repeatedValue("--channel", channels); !why.empty()) {
    return program::refuse("gimbalsim_log2csv", why);
  }
  if (const std::string why = Channels::prefixProblem(prefix); prefix_given && !why.empty()) {
    return refuse("--channel-prefix '" + prefix + "': " + why);
  }
  Type forced = Type::Unknown;
  if (!type_name.empty()) {
    for (const TypeInfo& t : kTypes) {
      if (type_name == t.name) forced = t.type;
    }
    if (forced == Type::Unknown) {
      return refuse("--type '" + type_name + "': expected truth, status, command, loop_stats, attitude or antenna");
    }
    if (channels.empty()) return refuse("--type needs --channel (the channel(s) to decode as " + type_name + ")");
  }

  std::error_code ec;
  const fs::file_status st = fs::status(log_path, ec);
  if (ec || !fs::exists(st)) return refuse("log '" + log_path + "': no such file");
  if (!fs::is_regular_file(st)) return refuse("log '" + log_path + "': not a regular file");
  // Pass 1: every event header validated (lcm_wire::LogReader), and which channels the log holds.
  // (An empty file is a log with no events: lcm-logger with nothing recorded leaves one.)
  std::map<std::string, long long> counts;
  std::uint64_t cut_bytes = 0, cut_offset = 0;  // a truncated log: its partial last event
  {
    lcm_wire::LogReader lr;
    if (std::string why; !lr.open(log_path, &why)) return refuse(why);
    lcm_wire::LogEvent e;
    while (lr.next(&e)) ++counts[std::string(e.channel)];
    if (lr.truncated()) {
      cut_bytes = lr.cutBytes();
      cut_offset = lr.errorOffset();
    } else if (!lr.error().empty()) {
      const bool first = lr.errorOffset() == 0;
      return refuse("log '" + log_path + "': " + (first ? "not an LCM log: " : "") + lr.error() +
                    "; nothing written");
    }
  }
  long long whole_events = 0;
  for (const auto& [ch, n] : counts) whole_events += n;
  if (cut_bytes > 0 && whole_events == 0) {  // nothing to salvage: a refusal, not a partial result
    return refuse("log '" + log_path + "': cut inside its first event (" + std::to_string(cut_bytes) +
                  " bytes): no whole event to convert; nothing written");
  }
  if (cut_bytes > 0) {
    std::fprintf(stderr,
                 "gimbalsim_log2csv: warning: log '%s' is cut inside its last event (a killed logger leaves one): "
                 "the last %llu bytes, from byte offset %llu, are dropped; the %lld whole events before them are "
                 "converted (exit %d)\n",
                 log_path.c_str(), static_cast<unsigned long long>(cut_bytes),
                 static_cast<unsigned long long>(cut_offset), whole_events, program::kPartial);
  }
  // A channel name is anyone's bytes on the bus (gimbalsim_record keeps them): shown, never printed raw (pass 111:
  // U+202E and an escape sequence reached the terminal from --list and this refusal; pass 113: 0x9B, a tab)
  auto present = [&] {
    std::string s;
    for (const auto& [ch, n] : counts) s += (s.empty() ? "" : ", ") + shownText(ch, true);
    return s.empty() ? std::string("none: the log has no events") : s;
  };
  if (list) {
    for (const auto& [ch, n] : counts) {
      const Type t = typeOfChannel(ch);
      std::printf("%-32s %10lld  %s\n", shownText(ch, true).c_str(), n,
                  t == Type::Unknown ? "(not a gimbalsim channel)" : typeName(t));
    }
    return cut_bytes > 0 ? program::kPartial : program::kOk;
  }

  // Selection: channel -> type.
  std::map<std::string, Type> selected;
  if (!channels.empty()) {
    for (const std::string& ch : channels) {
      if (counts.count(ch) == 0) return refuse("--channel '" + ch + "': not in the log (channels: " + present() + ")");
      std::string p;
      const Type t = forced != Type::Unknown ? forced : typeOfChannel(ch, &p);
      if (t == Type::Unknown) {
        return refuse("--channel '" + ch + "': not a gimbalsim channel name ([PREFIX]GIMBAL_TRUTH, ...); give --type");
      }
      if (prefix_given && forced == Type::Unknown && p != prefix) {
        return refuse("--channel '" + ch + "' does not carry --channel-prefix '" + prefix + "'");
      }
      selected[ch] = t;
    }
  } else {
    for (const auto& [ch, n] : counts) {
      std::string p;
      const Type t = typeOfChannel(ch, &p);
      if (t != Type::Unknown && (!prefix_given || p == prefix)) selected[ch] = t;
    }
    if (selected.empty()) {
      return refuse(std::string(prefix_given ? "no channel with --channel-prefix '" + prefix + "'" : "no gimbalsim channel") +
                    " in the log (channels: " + present() + ")");
    }
  }
  if (!out_file.empty() && selected.size() != 1) {
    return refuse("--out needs exactly one channel, the selection has " + std::to_string(selected.size()) +
                  " (use --channel, or --out-dir)");
  }

  // Pass 2: convert.
  const fs::path dir = out_dir.empty() ? fs::path(log_path).parent_path() : fs::path(out_dir);
  if (!out_dir.empty()) {
    if (const std::string why = io::outputFolderProblem(out_dir, true); !why.empty()) {
      return refuse("--out-dir '" + out_dir + "': " + why);
    }
  }
  const std::string stem = fs::path(log_path).stem().string();
  std::map<std::string, std::unique_ptr<io::OutputFile>> files;
  std::map<std::string, std::unique_ptr<Sink>> sinks;
  std::map<std::string, std::string> paths;
  for (const auto& [ch, t] : selected) {
    // A channel name comes from the log: one such as "/../../x" would have named a file outside the folder.
    if (out_file.empty() && !Channels::upperSnake(ch)) {
      return refuse("--channel '" + ch + "': only A-Z, 0-9 and '_' can name its CSV file; give --out FILE");
    }
    const std::string path = !out_file.empty() ? out_file : (dir / (stem + "_" + ch + ".csv")).string();
    std::unique_ptr<io::OutputFile> f;
    try {
      f = std::make_unique<io::OutputFile>(path, std::vector<std::string>{log_path});
    } catch (const io::OutputError& e) {
      return e.unwritable() ? program::unwritable("gimbalsim_log2csv", e.what()) : refuse(e.what());
    }
    sinks[ch] = std::make_unique<Sink>(t, f->stream(), log_time);
    files[ch] = std::move(f);
    paths[ch] = path;
  }
  {
    lcm_wire::LogReader lr;
    if (std::string why; !lr.open(log_path, &why)) return refuse(why);
    lcm_wire::LogEvent e;
    while (lr.next(&e)) {
      const auto it = sinks.find(std::string(e.channel));
      if (it != sinks.end()) it->second->add(e);
    }
    if (!lr.error().empty() && !(lr.truncated() && lr.errorOffset() == cut_offset)) {
      return refuse("log '" + log_path + "' changed while read: " + lr.error());
    }
  }
  // A channel none of whose messages decodes as its type (a wrong --type, or garbage) would give a CSV of a
  // header only, read as "the bench sent nothing": a channel named by --channel is refused, as one not in the
  // log is; one found by its name gets no CSV, and the console says why.
  std::vector<io::OutputFile*> members;
  std::vector<std::string> empty;
  for (const auto& [ch, s] : sinks) {
    if (s->rows > 0) {
      members.push_back(files[ch].get());
      continue;
    }
    const std::string why = "none of its " + std::to_string(counts[ch]) + " message(s) is a whole, finite " +
                            typeName(selected[ch]) + " (" + std::to_string(s->undecodable) + " not one, " +
                            std::to_string(s->non_finite) + " with a NaN or Inf)";
    if (!channels.empty() || sinks.size() == 1) {
      const std::string named = channels.empty() ? "channel '" : "--channel '";
      return refuse(named + ch + "': " + why + (forced != Type::Unknown ? ": is --type right?" : "") +
                    "; nothing written");
    }
    empty.push_back(ch + ": " + why + "; no CSV written for it");
  }
  if (members.empty()) return refuse("no channel of the log has a message to convert; nothing written");
  // The channels' CSVs are one run's outputs: all of them under their names, or none (one left beside
  // four lost ones was announced with the rest).
  if (io::CommitGroup group(members); !group.commit()) {
    std::fprintf(stderr, "gimbalsim_log2csv: error: %s; no CSV written\n", group.error().c_str());
    return program::kOutput;  // a lost output outranks a cut input
  }
  const int rc = cut_bytes > 0 ? program::kPartial : program::kOk;
  for (const std::string& line : empty) std::printf("%s\n", line.c_str());
  for (auto& [ch, s] : sinks) {
    if (s->rows == 0) continue;
    const long long rows = s->rows, bad = s->undecodable;
    std::printf("%s (%s): %lld rows -> %s\n", ch.c_str(), typeName(selected[ch]), rows, paths[ch].c_str());
    if (bad > 0) {
      std::printf("  %lld message(s) on %s are not a %s (garbage, another type or trailing bytes): skipped\n", bad,
                  ch.c_str(), typeName(selected[ch]));
    }
    if (s->non_finite > 0) {
      std::printf("  %lld message(s) on %s carry a NaN or Inf (no value a CSV cell holds; no bench program sends "
                  "one): skipped\n", s->non_finite, ch.c_str());
    }
  }
  return rc;
}

}  // namespace
}  // namespace gimbalsim::firmware

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("gimbalsim_log2csv", [&] { return gimbalsim::firmware::mainImpl(argc, argv); });
}
