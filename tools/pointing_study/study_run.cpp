#include "study_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "gimbalsim/controllers/pointing_controller.hpp"
#include "gimbalsim/dynamics/step_result.hpp"
#include "gimbalsim/dynamics/variant.hpp"
#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"

namespace gimbalsim::pointing_study {

using controllers::ControllerConfig;
using controllers::PointingController;

namespace {

/// What the loop closes on: the joint encoders and rates and the base's gyro
/// and star tracker, and the antenna's tracker and gyro when the plant has
/// them and the controller uses them (antenna.tracker).
std::string loopSensors(const firmware::PlantScene& ps, const ControllerConfig& c) {
  return ps.sensors.antenna_sensors && c.antenna.use_tracker ? "encoders+base attitude+antenna" : "encoders+base attitude";
}

/// A CSV number (io::appendCsvNumber: round trip, no -0).
std::string csvNum(double x) {
  std::string s;
  gimbalsim::io::appendCsvNumber(s, x);
  return s;
}

/// A run's error column in the CSV convention: "c=0.25mm" -> "error_c0p25mm_rad".
std::string errorColumn(const std::string& label) {
  std::string c = "error_";
  for (char ch : label) {
    if (ch == '.') {
      c += 'p';
    } else if (ch != '=') {
      c += ch;
    }
  }
  return c + "_rad";
}

/// The scene key of the limit that stopped a run, from its status (never its message's text).
std::string stopKey(const firmware::ClosedLoopResult& r) {
  if (r.rejected_stop) return "commands_rejected";
  if (r.stop_status == StepStatus::Ok) return "refused";
  return *limitKey(r.stop_status) ? limitKey(r.stop_status) : "non_finite";
}

}  // namespace

Study runOne(const firmware::PlantScene& ps, const ControllerConfig& c, const firmware::ClosedLoopOptions& opt,
             std::string scene_name, std::string label, double clearance, std::string sensors) {
  Study s;
  s.label = std::move(label);
  s.scene = std::move(scene_name);
  s.joints = std::string(kindName(ps.scene.model.joint1_kind)) + "/" + kindName(ps.scene.model.joint2_kind);
  s.sensors = std::move(sensors);
  s.loop_sensors = loopSensors(ps, c);
  s.clearance = clearance;
  PointingController controller(c);
  const firmware::ClosedLoopResult r = firmware::runClosedLoop(ps, controller, c.profile, opt,
                                                               [&](const firmware::TickRecord& t) {
    s.err.push_back(t.truth_error);
    s.peak_run = std::max(s.peak_run, t.truth_error);
    if (t.ref.segment == pointing::Segment::Track) ++s.track_ticks;
  });
  // The closed loop's own track figures: one definition of the window and of "not reached".
  s.peak_track = r.max_truth_error_track;
  s.rms_track = r.rms_truth_error_track;
  s.track_reason = r.track_reason;
  // The window's rule for its tick count too: a run ending at the track's start instant records that instant
  // (its last state) but has not reached the window, and counts no track tick (pass 59: 1 beside "not reached").
  if (!s.track_reason.empty()) s.track_ticks = 0;
  s.controller_limited_ticks = r.controller_limited_ticks;
  s.controller_limited_track = r.controller_limited_ticks_track;
  s.motor_limited_ticks = r.motor_limited_ticks;
  s.max_tilt[0] = r.max_tilt(0), s.max_tilt[1] = r.max_tilt(1);
  s.play_onset[0] = r.play_onset(0), s.play_onset[1] = r.play_onset(1);
  for (int j = 0; j < 2; ++j) {  // NaN means "not over the ticks run": say how far that was
    if (!std::isnan(s.play_onset[j])) continue;
    char why[160];
    std::snprintf(why, sizeof why, "%saxis %d never on its backlash guard's gains in the %lld ticks run%s",
                  s.onset_reason.empty() ? "" : "; ", j + 1, r.ticks, r.ok ? "" : " (the run stopped)");
    s.onset_reason += why;
  }
  // The closed loop's rule for a whole-run figure: none over no tick, nor over the first tick alone of a run
  // whose first step failed (it wrote 0, pass 53).
  s.run_reason = r.run_reason;
  if (!s.run_reason.empty()) s.peak_run = std::numeric_limits<double>::quiet_NaN();
  s.ok = r.ok;
  s.interrupted = r.interrupted;
  if (!r.ok) {
    s.stop_key = stopKey(r);
    s.reason = r.stopReason();  // as every reader of a bench run names it
  }
  return s;
}

std::string timeSeriesCsv(const std::vector<Study>& runs, double period) {
  std::size_t n = 0;
  std::string out = "t_s";
  for (const Study& s : runs) {
    out += ',';
    out += errorColumn(s.label);
    n = std::max(n, s.err.size());
  }
  out += "\n";
  for (std::size_t k = 0; k < n; ++k) {
    out += csvNum(static_cast<double>(k) * period);
    for (const Study& s : runs) {
      out += ',';
      if (k < s.err.size()) out += csvNum(s.err[k]);
    }
    out += "\n";
  }
  return out;
}

std::string summaryCsv(const std::vector<Study>& runs) {
  std::string out =
      "run,scene,sensors,clearance_m,peak_track_rad,rms_track_rad,peak_run_rad,track_ticks,controller_limited_ticks,"
      "controller_limited_track_ticks,motor_limited_ticks,joints,max_tilt1_rad,max_tilt2_rad,play_onset1_s,"
      "play_onset2_s,loop_sensors,status,stop_reason,track_reason,onset_reason\n";
  const auto text = [](const std::string& t) { return io::csvTextCell(t) + ","; };  // unquoted (CSV convention)
  const auto num = [](double x) { return csvNum(x) + ","; };
  for (const Study& s : runs) {
    out += text(s.label) + text(s.scene) + text(s.sensors) + num(s.clearance) + num(s.peak_track) +
           num(s.rms_track) + num(s.peak_run) + std::to_string(s.track_ticks) + "," +
           std::to_string(s.controller_limited_ticks) + "," +
           // a count over the track window: nan (track_reason says why) when the run never reached it
           (s.track_reason.empty() ? std::to_string(s.controller_limited_track) : std::string("nan")) + "," +
           std::to_string(s.motor_limited_ticks) + "," +
           text(s.joints) + num(s.max_tilt[0]) + num(s.max_tilt[1]) + num(s.play_onset[0]) + num(s.play_onset[1]) +
           text(s.loop_sensors) +
           text(s.ok ? std::string("ok") : "stop:" + s.stop_key) + text(s.reason) + text(s.track_reason) +
           io::csvTextCell(s.onset_reason) + "\n";
  }
  return out;
}

}  // namespace gimbalsim::pointing_study
