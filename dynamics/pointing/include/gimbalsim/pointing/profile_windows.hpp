// The profile's windows (slew, hold, track) as times, and why a figure over
// one has no value: the definition of the phase boundaries that the closed
// loop's figures, the C++ tools' summaries and the Python package's spec
// checks use (the LCM bench script tools/hil/tune_sweep.py reads the same keys) (TargetProfile::at switches segments at the same times).
#pragma once

#include <string>

#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::pointing {

/// A window of the profile, [start_s, end_s); the track's end is +inf.
struct ProfileWindow {
  Segment segment = Segment::Track;
  double start_s = 0.0;
  double end_s = 0.0;
};

/// The window of segment s (Wait: [0, slew_start)).
ProfileWindow profileWindow(const TargetProfile& p, Segment s) noexcept;

/// How much of a window a figure needs (docs/usage.md "Figures over a window").
enum class WindowNeed : std::uint8_t {
  Part,  ///< a figure over the window (a max, an RMS): the run must go past its start
  End,   ///< a figure at the window's end (hold end, settling time): the run must reach its end
};

/// Why a run that ended at t_end_s has no figure over w ("" if it has one):
/// "track window [3.5, inf) s not reached: run ended at 2 s". An empty
/// window (hold_time 0) has no figure either.
std::string windowNotReached(const ProfileWindow& w, WindowNeed need, double t_end_s);

/// The console form of a figure: its value with printf format fmt, or
/// "n/a (<reason>)" when it has none.
std::string figureText(double value, const std::string& reason, const char* fmt);

}  // namespace gimbalsim::pointing
