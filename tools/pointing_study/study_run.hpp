// One run of gimbalsim_pointing_study (main.cpp) and the CSV files its runs
// make: the closed loop in process, its truth error per tick and the figures
// of its summary row.
#pragma once

#include <string>
#include <vector>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/firmware_sim/closed_loop.hpp"

namespace gimbalsim::pointing_study {

/// One closed-loop run and what it measured.
struct Study {
  std::string label;        ///< column name: "ideal", "c=0.25mm" (one clearance scene), "paper_spatial2_c=0.25mm"
  std::string scene;        ///< scene name
  std::string sensors;      ///< "perfect" (the scene's sensors), "realistic" (main.cpp's kRealisticSensors) or "tracker" (main.cpp's kTrackerSensors)
  std::string loop_sensors; ///< what the controller closed its loop on (loopSensors)
  double clearance = 0.0;   ///< [m], 0 for the ideal joint
  std::vector<double> err;  ///< truth pointing error per tick [rad]
  double peak_track = 0.0, rms_track = 0.0, peak_run = 0.0;  ///< the track's: NaN with track_reason if not reached
  long long track_ticks = 0;
  long long controller_limited_ticks = 0;  ///< ticks with the command at the controller's limit (either axis)
  long long controller_limited_track = 0;  ///< of them, while tracking
  long long motor_limited_ticks = 0;       ///< ticks with the applied torque at the motor limit (either axis)
  std::string joints;       ///< the joints' kinds, "ideal/spatial" (azimuth/elevation)
  double max_tilt[2] = {};  ///< [rad] largest tilt of each joint's journal at the ticks (0 unless spatial)
  /// [s] when each axis went onto its backlash guard's gains (NaN: never; controllers' play_guard.hpp)
  double play_onset[2] = {};
  std::string track_reason;  ///< why the track figures are NaN ("" if they have values)
  std::string run_reason;    ///< why peak_run is NaN (the closed loop's run_reason; "" if it has a value)
  std::string onset_reason;  ///< why a play_onset is NaN ("" if both have values)
  bool ok = true;
  bool interrupted = false;  ///< a stop request ended it (ClosedLoopOptions::stop_requested): not a whole run
  std::string stop_key;     ///< the scene key of the limit that stopped the plant ("" if none)
  std::string reason;       ///< why it stopped
};

/// Runs one closed loop of the study: the truth error per tick and the summary's figures.
/// scene_name: the scene file's stem, as every table of the study names it (not its `name:` key).
Study runOne(const firmware::PlantScene& ps, const controllers::ControllerConfig& c,
             const firmware::ClosedLoopOptions& opt, std::string scene_name, std::string label, double clearance,
             std::string sensors);

/// pointing_error.csv: t_s and each run's truth error column (a run that stopped has empty cells after).
std::string timeSeriesCsv(const std::vector<Study>& runs, double period);

/// summary.csv: one row per run.
std::string summaryCsv(const std::vector<Study>& runs);

}  // namespace gimbalsim::pointing_study
