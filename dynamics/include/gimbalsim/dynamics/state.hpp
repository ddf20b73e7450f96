// State: small, copyable; copying one is how the integrator steps back, and
// a copy is a checkpoint (everything that changes future results is here).
#pragma once

#include <array>

#include "gimbalsim/dynamics/variant.hpp"
#include "gimbalsim/dynamics/run_spec.hpp"

namespace gimbalsim {

/// Generalised coordinates. Floating base: q = [p_W (3) [m], quaternion
/// (w, x, y, z) of R_WB (4), chain (NJ)], v = [omega_B (3) [rad/s], v_B (3)
/// [m/s] (base CoM velocity, base frame), chain rates (NJ)]. The chain is
/// joint 1's group then joint 2's (variant.hpp), e.g. ideal [theta1, theta2],
/// planar joint 2 [theta1, ecc_x, ecc_y, theta2] ([rad], [m], [m], [rad]);
/// ecc is the journal centre relative to the bearing centre in the joint's
/// plane basis (u1, u2).
template <class V>
struct State {
  static constexpr int NQ = V::NQ, NV = V::NV, NB = V::NB, NJ = V::NJ;
  static constexpr int QJ = V::kFloating ? 7 : 0;  ///< first chain index in q
  using VecQ = Eigen::Matrix<double, NQ, 1>;
  using VecV = Eigen::Matrix<double, NV, 1>;

  double t = 0.0;        ///< [s]
  VecQ q = VecQ::Zero();
  VecV v = VecV::Zero();
  // Discrete contact memory, one entry per contact end (V::NC: a planar
  // joint has one end, a spatial joint two, joint 1's first), changed only
  // at located switches.
  std::array<bool, V::NC> in_contact{};  ///< side of each end's last located switch
  std::array<double, V::NC> v0{};        ///< normal velocity at the onset of each end's impact [m/s]
  /// friction.law coulomb_stick only (one planar contact end): +1 / -1
  /// slipping with v_t > 0 / < 0, 0 sticking (meaningful while in_contact).
  int friction_mode = 0;
  /// coulomb_stick, slipping: a v_t reversal is friction_mode * v_t below
  /// this, min(0, friction_mode * v_t) at the start of the slip (a slip that
  /// starts from v_t = 0 may start a round-off on the wrong side) [m/s]
  double vt_floor = 0.0;
  /// sim.substep_policy adaptive: the contact sub-step to try next [s]
  /// (0 = none chosen yet). Part of the state so that a copied State is a
  /// full checkpoint: stepping the copy reproduces the run bit for bit.
  double h_next = 0.0;

  /// Any contact end in contact.
  bool anyInContact() const {
    for (const bool c : in_contact) {
      if (c) return true;
    }
    return false;
  }
  double theta(int joint) const { return q(QJ + V::theta(joint)); }
  double dtheta(int joint) const { return v(NB + V::theta(joint)); }
};

/// What enters the plant each step: one control-injection point.
struct Input {
  Vec2 tau = Vec2::Zero();  ///< joint torques tau1 (azimuth), tau2 (elevation) [N m]
};

/// Initial state of a scene: base at rest at the origin, joints as the scene says.
template <class V>
State<V> initialState(const InitialParams& init) {
  State<V> s;
  if constexpr (V::kFloating) s.q(3) = 1.0;  // identity quaternion
  constexpr int QJ = State<V>::QJ, NB = V::NB;
  s.q(QJ + V::theta(0)) = init.theta1;
  s.q(QJ + V::theta(1)) = init.theta2;
  s.v(NB + V::theta(0)) = init.dtheta1;
  s.v(NB + V::theta(1)) = init.dtheta2;
  if constexpr (V::kKind1 != ClearanceKind::Ideal) {  // each journal's initial eccentricity
    s.q(QJ + V::G1) = init.ecc[0].x();
    s.q(QJ + V::G1 + 1) = init.ecc[0].y();
  }
  if constexpr (V::kKind2 != ClearanceKind::Ideal) {
    s.q(QJ + V::G2) = init.ecc[1].x();
    s.q(QJ + V::G2 + 1) = init.ecc[1].y();
  }
  if constexpr (V::kKind1 == ClearanceKind::Spatial) {  // each spatial journal's initial tilt: alpha, beta
    s.q(QJ + V::G1 + 2) = init.tilt[0].x();
    s.q(QJ + V::G1 + 3) = init.tilt[0].y();
  }
  if constexpr (V::kKind2 == ClearanceKind::Spatial) {
    s.q(QJ + V::G2 + 2) = init.tilt[1].x();
    s.q(QJ + V::G2 + 3) = init.tilt[1].y();
  }
  return s;
}

}  // namespace gimbalsim
