// gimbalsim_controller_floor's rows and tables (floor_table.hpp).
#include "floor_table.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "gimbalsim/controllers/pointing_controller.hpp"
#include "gimbalsim/firmware_sim/closed_loop.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"
#include "gimbalsim/program/stop_signal.hpp"

namespace gimbalsim::floor_study {
namespace {

/// A window's figure in the console form of every tool (pointing::figureText):
/// "n/a (...)" for a window without a tick; the table's notes say why in full
/// (the window and where the run ended), once, as every row ends at one time.
std::string sci(double x, const std::string& why) {
  return pointing::figureText(x, why.empty() ? "" : "not reached, see below", "%.3e");
}

/// When the after-slew max occurred [s], or that there is none.
std::string at(const Row& r) {
  return pointing::figureText(r.after_slew.t_max_s, r.after_slew_why.empty() ? "" : "not reached, see below", "%.3f");
}

/// The table's notes: each distinct reason a figure has none, one line each.
std::string notes(const std::vector<Row>& rows) {
  std::vector<std::string> whys;
  for (const Row& r : rows) {
    for (const std::string& w : {r.after_slew_why, r.track_why}) {
      if (!w.empty() && std::find(whys.begin(), whys.end(), w) == whys.end()) whys.push_back(w);
    }
  }
  std::string s;
  for (const std::string& w : whys) s += "n/a: " + w + "\n";
  return s;
}

std::string ratio(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b)) return "n/a (a window not reached)";
  // A profile that never moves the antenna leaves both errors 0: no ratio to give (it printed -nan, pass 56).
  return b > 0.0 ? formatSignificant(a / b, 3) : "n/a (the clearance run's error is 0)";
}

}  // namespace

std::string afterSlewNotReached(double slew_end_s, double t_end_s) {
  if (t_end_s > slew_end_s) return "";
  // Six significant digits, as the closed loop's track reason: a tick count times the period is 0.10200000000000001.
  return "after-slew window [" + formatSignificant(slew_end_s, 6) + ", inf) s not reached: run ended at " +
         formatSignificant(t_end_s, 6) + " s";
}

Row runOne(const firmware::PlantScene& ps, const controllers::ControllerConfig& c, double duration, std::string label) {
  Row r;
  r.label = std::move(label);
  controllers::PointingController controller(c);
  firmware::ClosedLoopOptions opt;
  opt.duration = duration;
  opt.stop_requested = io::stopRequested;  // SIGINT/SIGTERM: ends the run within kStopCheckTicks ticks
  const double slew_end = c.profile.slewEnd();
  const firmware::ClosedLoopResult res =
      firmware::runClosedLoop(ps, controller, c.profile, opt, [&](const firmware::TickRecord& t) {
        if (t.t >= slew_end) r.after_slew.add(t.truth_error, t.t);
        if (t.profile.segment == pointing::Segment::Track) {
          r.track.add(t.truth_error);
          r.joint_track.add((t.ref.q - t.theta_true).cwiseAbs().maxCoeff());
          r.attitude_track.add(t.attitude_error);
        }
      });
  // The closed loop's rule for a window (docs/usage.md "Figures over a window"): a figure only if
  // the run's last tick lies after the window's start; a last tick at 3.5 s is no track.
  r.track_why = res.track_reason;
  r.after_slew_why = afterSlewNotReached(slew_end, res.t_end);
  if (!r.track_why.empty()) r.track = r.joint_track = r.attitude_track = Stat{};
  if (!r.after_slew_why.empty()) r.after_slew = Stat{};
  r.ok = res.ok;
  r.why = res.stopReason();  // a plant's stop at its last good state, as the study and the bench name it
  return r;
}

std::string table(const std::string& title, const std::vector<Row>& rows, bool markdown) {
  std::string s;
  if (markdown) {
    s += "**" + title + "**\n\n";
    s += "| run | track max [rad] | track RMS [rad] | after-slew max [rad] | at [s] | after-slew RMS [rad] | joint err "
         "track max [rad] | attitude err track max [rad] | plant |\n|---|---|---|---|---|---|---|---|---|\n";
  } else {
    char b[256];
    std::snprintf(b, sizeof b, "# %s\n%-10s %13s %13s %13s %7s %13s %13s %13s  %s\n", title.c_str(), "run",
                  "trk_max", "trk_rms", "slew+_max", "at_s", "slew+_rms", "joint_trk", "att_trk", "plant");
    s += b;
  }
  for (const Row& r : rows) {
    const std::string plant = r.ok ? "ok" : "stop: " + r.why;
    if (markdown) {
      s += "| " + r.label + " | " + sci(r.track.peak(), r.track_why) + " | " + sci(r.track.rms(), r.track_why) +
           " | " + sci(r.after_slew.peak(), r.after_slew_why) + " | " + at(r) + " | " +
           sci(r.after_slew.rms(), r.after_slew_why) + " | " + sci(r.joint_track.peak(), r.track_why) + " | " +
           sci(r.attitude_track.peak(), r.track_why) + " | " + plant + " |\n";
    } else {
      char b[1024];
      std::snprintf(b, sizeof b, "%-10s %13s %13s %13s %7s %13s %13s %13s  %s\n", r.label.c_str(),
                    sci(r.track.peak(), r.track_why).c_str(), sci(r.track.rms(), r.track_why).c_str(),
                    sci(r.after_slew.peak(), r.after_slew_why).c_str(), at(r).c_str(),
                    sci(r.after_slew.rms(), r.after_slew_why).c_str(), sci(r.joint_track.peak(), r.track_why).c_str(),
                    sci(r.attitude_track.peak(), r.track_why).c_str(), plant.c_str());
      s += b;
    }
  }
  const std::string under = notes(rows);
  s += markdown && !under.empty() ? "\n" + under : under;
  if (rows.size() >= 2) {
    const Row &i = rows[0], &c = rows[1];
    const std::string line = "ideal / " + c.label + ": track max " + ratio(i.track.peak(), c.track.peak()) +
                             ", track RMS " + ratio(i.track.rms(), c.track.rms()) + ", after-slew max " +
                             ratio(i.after_slew.peak(), c.after_slew.peak()) + ", after-slew RMS " +
                             ratio(i.after_slew.rms(), c.after_slew.rms()) + " (goal: each <= 0.2)";
    s += markdown ? "\n" + line + "\n\n" : line + "\n";
  }
  return s;
}

}  // namespace gimbalsim::floor_study
