// RunSpec: how a scene is run, as opposed to what it is (Model). The
// dynamics never reads it; simulate(), firmware_sim, the closed loop and the
// tools do. Loaded from the same scene file (scene.hpp).
#pragma once

#include <string>
#include <vector>

#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim {

/// Initial state (docs/MODEL.md 1.6: everything at rest, journal concentric).
struct InitialParams {
  double theta1 = 0.0, theta2 = 0.0;    ///< [rad]
  double dtheta1 = 0.0, dtheta2 = 0.0;  ///< [rad/s]
  Vec2 ecc = Vec2::Zero();              ///< journal centre in the joint plane [m]
};

/// Sensors as the gimbal firmware reports them (firmware_sim and the closed loop).
struct SensorParams {
  double encoder_resolution = 5.992112452678286e-6;  ///< 2 pi / 2^20 [rad]; 0 = unquantized
  double encoder_noise = 0.0;   ///< Gaussian encoder noise sigma, before quantization [rad]
  double rate_noise = 0.0;      ///< Gaussian rate noise sigma [rad/s]
  long long seed = 1;           ///< noise generator seed (>= 0)
};

struct RunSpec {
  double duration = 5.0;            ///< simulated time [s]
  double output_interval = 1.0e-3;  ///< CSV row spacing [s], a multiple of sim.step
  Vec2 torque{5.0, 10.0};           ///< constant joint torques tau1, tau2 [N m] (simulate only)
  Vec2 torque_limit{1.0e3, 1.0e3};  ///< motor limit per axis [N m] (firmware, closed loop)
  InitialParams initial;
  SensorParams sensors;
};

/// A loaded scene (scene.hpp): the physics (Model) and how to run it (RunSpec).
struct Scene {
  Model model;
  RunSpec run;
  std::vector<std::string> warnings;  ///< accepted but suspicious (e.g. triangle inequality)
};

}  // namespace gimbalsim
