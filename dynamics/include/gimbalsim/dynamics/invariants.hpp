// Invariant monitor of a run: the momentum of the free-floating system and
// the energy balance, checked at every output row by simulate() against
// sim.momentum_tol and sim.energy_tol (a run that breaks them stops with a
// diagnostic naming the key instead of going on wrong), and used by the
// stress classifier (tools/stress/) with the same definitions.
#pragma once

#include <string>

#include "gimbalsim/dynamics/model.hpp"
#include "gimbalsim/dynamics/observables.hpp"

namespace gimbalsim {

/// True when no damping or friction can act, so the energy balance must be held.
bool conservative(const Model& m);
/// False with a spatial clearance joint: its contact force does work that the
/// Hertz potential does not hold (first order in the tilt, docs/MODEL.md 2.7)
/// and its motor couple also works on the tilt, so the energy balance is not
/// an invariant there and sim.energy_tol is not checked (momentum still is).
bool energyBalanceHeld(const Model& m);

/// Energy balance and momentum along the output rows.
///
/// Energy: B(t) = T(t) + U(t) - W(t), with T the kinetic energy (row.energy),
/// U = K delta^(n+1) / (n+1) the energy stored in the Hertz springs, and W the
/// work of the joint torques. The scene's torques are constant couples about
/// the joint axes, so W = tau1 (theta1(t) - theta1(0)) + tau2 (theta2(t) -
/// theta2(0)) exactly: no quadrature error (theta2 is the relative rotation of
/// the journal in the bearing, which is what the joint-2 couple works on).
/// Damping and friction only take energy out, so B never rises; when neither
/// can act (no damping law or c_e = 1, and no friction) B is also held.
///
/// Momentum (floating base): the drift of P and L from their first row,
/// relative to scales of the momenta the bodies carry (an exactly conserved
/// zero total momentum would otherwise have no scale).
class InvariantMonitor {
 public:
  /// torque: the constant joint torques whose work enters the energy balance [N m].
  InvariantMonitor(const Model& m, const Vec2& torque);
  /// angular_scale, linear_scale: sums over the bodies of |L_body| [N m s]
  /// and |p_body| [N s] at this row (momentum().scale, .scale_linear); 0
  /// when unknown (the linear scale then has a lower bound from the row).
  /// hertz_energy: the energy stored in every contact end's spring at this row [J].
  void feed(const Row& r, double hertz_energy, double angular_scale = 0.0, double linear_scale = 0.0);

  double maxRise() const { return max_rise_; }      ///< max B(t_k) - min_{j<k} B(t_j) [J]
  double maxChange() const { return max_change_; }  ///< max |B(t) - B(0)| [J]
  double scale() const { return scale_; }           ///< max over rows of T + U, |W| [J]
  double finalChange() const { return b_last_ - b0_; }  ///< B(end) - B(0) [J]
  /// max over rows of sum_i |p_i| (given), of its lower bound |P(0)| + 2
  /// m_base |v_base| (the base's momentum and the chain's, which carries the
  /// rest of P), and of sum_i |l_i| / chainReach() (docs/MODEL.md 8.3) [N s]
  double linearScale() const { return lin_scale_; }
  double angularScale() const { return ang_scale_; }  ///< max over rows of sum |L_body| [N m s]
  /// The farthest any chain body's centre of mass can lie from the base's (joint offsets plus centre-of-mass
  /// offsets along the chain) [m]; 0 for a chain with none.
  double chainReach() const { return reach_; }
  double maxDriftLinear() const { return drift_lin_; }   ///< max |P - P(0)| [N s]
  double maxDriftAngular() const { return drift_ang_; }  ///< max |L - L(0)| [N m s]
  double maxPenetration() const { return max_delta_; }   ///< over rows [m]
  bool finite() const { return finite_; }
  long long rows() const { return rows_; }

  // Relative measures (0 when nothing moved, +inf with drift but no scale).
  double energyRiseRel() const { return relative(max_rise_, scale_); }
  double energyChangeRel() const { return relative(max_change_, scale_); }
  double energyFinalRel() const { return relative(finalChange(), scale_); }
  double linearDriftRel() const { return relative(drift_lin_, lin_scale_); }
  double angularDriftRel() const { return relative(drift_ang_, ang_scale_); }

  /// The first of sim.momentum_tol / sim.energy_tol the rows so far break
  /// (bounds of 0 are off): its key and a message naming it; key "" when none.
  struct Violation {
    const char* key = "";
    std::string message;
    explicit operator bool() const { return *key != '\0'; }
  };
  Violation violation() const;

  static double relative(double x, double scale);

 private:
  const Model& m_;
  Vec2 torque_;
  bool conservative_ = false;
  bool energy_checked_ = true;  ///< energyBalanceHeld()
  long long rows_ = 0;
  double theta1_0_ = 0.0, theta2_0_ = 0.0;
  double b0_ = 0.0, b_min_ = 0.0, b_last_ = 0.0;
  double max_rise_ = 0.0, max_change_ = 0.0, scale_ = 0.0;
  double p0_ = 0.0, lin_scale_ = 0.0, ang_scale_ = 0.0, max_delta_ = 0.0;
  double reach_ = 0.0;  ///< chainReach() [m]
  double P0_[3] = {0, 0, 0}, L0_[3] = {0, 0, 0};
  double drift_lin_ = 0.0, drift_ang_ = 0.0;
  bool finite_ = true;
};

}  // namespace gimbalsim
