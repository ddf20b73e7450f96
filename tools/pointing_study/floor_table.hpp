#pragma once
// gimbalsim_controller_floor's rows: one closed-loop run's truth pointing
// figures over the track and after the slew, and the table of a controller's
// runs (console or Markdown) with the ratio ideal / first clearance.

#include <cmath>
#include <string>
#include <vector>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"

namespace gimbalsim::floor_study {

/// Max and RMS of a signal over a window (count 0: the window was not reached).
struct Stat {
  double max = 0.0, sum_sq = 0.0;
  double t_max_s = 0.0;  ///< when the max occurred [s]
  long long n = 0;
  void add(double x, double t_s = 0.0) {
    if (n == 0 || x > max) max = x, t_max_s = t_s;
    sum_sq += x * x;
    ++n;
  }
  double rms() const { return n > 0 ? std::sqrt(sum_sq / static_cast<double>(n)) : std::nan(""); }
  double peak() const { return n > 0 ? max : std::nan(""); }
};

struct Row {
  std::string label;
  Stat track, after_slew;       ///< truth pointing error [rad]
  Stat joint_track;             ///< max over axes |q_ref - theta_true| while tracking [rad]
  Stat attitude_track;          ///< estimated vs true base attitude while tracking [rad]
  std::string track_why, after_slew_why;  ///< why a window has no figure ("" when it has one)
  bool ok = true;
  std::string why;
};

/// Why a run ending at t_end_s has no figure after the slew ("" when it has):
/// the window and where the run ended, as the closed loop says it for the track.
std::string afterSlewNotReached(double slew_end_s, double t_end_s);

/// One in-process closed-loop run of duration [s] (stops on SIGINT/SIGTERM within the loop's check ticks).
Row runOne(const firmware::PlantScene& ps, const controllers::ControllerConfig& c, double duration, std::string label);

/// One controller's block: a row per scene, then the ratio ideal / first clearance.
std::string table(const std::string& title, const std::vector<Row>& rows, bool markdown);

}  // namespace gimbalsim::floor_study
