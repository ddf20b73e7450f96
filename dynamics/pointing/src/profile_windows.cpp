#include "gimbalsim/pointing/profile_windows.hpp"

#include <cstdio>
#include <limits>

#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim::pointing {
namespace {

std::string num(double x) { return formatSignificant(x, 6); }  // as printf's %g

}  // namespace

ProfileWindow profileWindow(const TargetProfile& p, Segment s) noexcept {
  switch (s) {
    case Segment::Wait: return {s, 0.0, p.slew_start};
    case Segment::Slew: return {s, p.slew_start, p.slewEnd()};
    case Segment::Hold: return {s, p.slewEnd(), p.trackStart()};
    case Segment::Track: break;
  }
  return {Segment::Track, p.trackStart(), std::numeric_limits<double>::infinity()};
}

std::string windowNotReached(const ProfileWindow& w, WindowNeed need, double t_end_s) {
  const std::string name = std::string(describe(w.segment)) + " window [" + num(w.start_s) + ", " + num(w.end_s) + ") s";
  if (!(w.end_s > w.start_s)) return name + " is empty";
  if (need == WindowNeed::Part && !(t_end_s > w.start_s)) {
    return name + " not reached: run ended at " + num(t_end_s) + " s";
  }
  if (need == WindowNeed::End && !(t_end_s >= w.end_s)) {
    return "end of the " + name + " not reached: run ended at " + num(t_end_s) + " s";
  }
  return "";
}

std::string figureText(double value, const std::string& reason, const char* fmt) {
  if (!reason.empty()) return "n/a (" + reason + ")";
  char b[64];
  std::snprintf(b, sizeof b, fmt, value);
  return b;
}

}  // namespace gimbalsim::pointing
