// RunSpec: how a scene is run, as opposed to what it is (Model). The
// step never reads it; simulate(), firmware_sim, the closed loop and the
// tools do. The sensors are the firmware's (firmware_sim/sensor_params.hpp). Loaded from the same scene file (scene.hpp).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim {

/// Initial state (docs/MODEL.md 1.6: everything at rest, journal concentric).
struct InitialParams {
  double theta1 = 0.0, theta2 = 0.0;    ///< [rad]
  double dtheta1 = 0.0, dtheta2 = 0.0;  ///< [rad/s]
  /// Each joint's journal centre in its joint plane (u1, u2) [m]: [0] joint 1, [1] joint 2.
  std::array<Vec2, 2> ecc{Vec2::Zero(), Vec2::Zero()};
  /// Each spatial joint's journal tilt [rad]: alpha about u1, then beta about
  /// the u2 it left (docs/MODEL.md 2.7); [0] joint 1, [1] joint 2.
  std::array<Vec2, 2> tilt{Vec2::Zero(), Vec2::Zero()};
};

/// What a run may ask for, checked by the scene's validate() before running
/// (naming the key), so every derived count fits a long long and an output
/// cannot fill a disk many times over.
struct RunBounds {
  static constexpr double kMaxSteps = 1e12;          ///< sim.duration / sim.step
  static constexpr double kMaxSubstepsPerStep = 1e7;  ///< sim.step / sim.substep (the sub-step cap is an int)
  static constexpr int kMaxEventIters = 1000000;      ///< sim.max_event_iters
  static constexpr double kCsvValueBytes = 20.0;     ///< worst "%.12g," per CSV value
  static constexpr double kMaxOutputBytes = 1e11;    ///< rows x columns x kCsvValueBytes: 100 GB
};

struct RunSpec {
  double duration = 5.0;            ///< simulated time [s]
  double output_interval = 1.0e-3;  ///< CSV row spacing [s], a multiple of sim.step
  Vec2 torque{5.0, 10.0};           ///< constant joint torques tau1, tau2 [N m] (simulate only)
  Vec2 torque_limit{1.0e3, 1.0e3};  ///< motor limit per axis [N m] (firmware, closed loop)
  InitialParams initial;
};

/// A loaded scene (scene.hpp): the physics (Model) and how to run it (RunSpec).
struct Scene {
  Model model;
  RunSpec run;
  /// The keys that give both joints (contact.*, friction.*, initial.ecc) as
  /// loaded: each joint's bearing (Model::bearing) and journal's initial
  /// eccentricity (RunSpec::initial) are these but where the scene gives
  /// the joint its own (docs/scene_keys.md "The two bearings").
  struct BothJoints {
    ContactParams bearing;
    Vec2 ecc = Vec2::Zero();  ///< [m]
    /// The joints' own keys the scene gave (jointN.contact.*, jointN.friction.*,
    /// initial.eccN; a clearance as the journal radius it sets): its values list
    /// them even where they equal the shared key, so a scene rebuilt from its
    /// values, with a shared key changed, keeps them.
    std::vector<std::string> own_keys;
  } both_joints;
  std::vector<std::string> warnings;  ///< accepted but suspicious (e.g. triangle inequality)
  /// Each override (its 1-based number among the loader's) that acts on nothing in this scene, with why.
  std::vector<std::pair<int, std::string>> idle_sets;
};

}  // namespace gimbalsim
