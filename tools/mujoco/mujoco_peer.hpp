// MuJoCo peer of the work-precision benchmark: the same floating-base gimbal
// with ideal joints built as an MJCF model (free joint base + two hinges,
// gravity off, constant joint torques through qfrc_applied, integrator RK4),
// measured against gimbalsim's reference with the same boresight metric.
// Optional: built only when Debian's libmujoco-dev is installed.
#pragma once

#include <string>
#include <vector>

#include "points.hpp"

namespace gimbalsim::workprec {

/// MJCF text of a floating-base, ideal-joint model. Frames: the base body
/// frame sits at the base CoM (MuJoCo's free joint qpos is the body frame's
/// position and quaternion, as our q is), each shaft's body frame at its
/// joint, inertias at the CoM via fullinertia. Throws for other variants.
std::string mjcfOf(const Model& m, double timestep);

/// MuJoCo RK4 at each timestep in `steps` (those dividing the output
/// interval), errors against ref at every output row, median thread CPU time
/// of `repeats` runs. A point that MuJoCo refuses (e.g. an inertia breaking
/// the triangle inequality) comes back not ok with MuJoCo's message.
std::vector<Point> mujocoPoints(const Scene& sc, const Trajectory& ref, const std::vector<double>& steps,
                                int repeats);

}  // namespace gimbalsim::workprec
