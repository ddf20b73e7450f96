// Data: the preallocated workspace of one simulation, sized at compile time by
// the Variant. Grouped by the stage that writes it. Nothing here allocates.
#pragma once

#include <array>

#include "gimbalsim/dynamics/mass_factor.hpp"
#include "gimbalsim/dynamics/spatial_joint.hpp"
#include "gimbalsim/dynamics/state.hpp"
#include "gimbalsim/dynamics/step_result.hpp"

namespace gimbalsim {

/// Contact quantities of one contact end at one evaluation (a planar
/// joint's contact, or one end plane of a spatial joint's bearing).
struct ContactEval {
  double e = 0.0;       ///< eccentricity magnitude (spatial: in the end plane) [m]
  Vec2 n = Vec2::Zero();  ///< unit normal in the joint plane basis (zero when e = 0)
  double delta = 0.0;   ///< penetration e - c [m] (negative: free)
  double vn = 0.0;      ///< normal relative velocity of the material points [m/s]
  /// tangential relative velocity of the material points: along t (planar),
  /// its magnitude in the tangent plane (spatial) [m/s]
  double vt = 0.0;
  double fn = 0.0;      ///< normal force magnitude [N]
  double ft = 0.0;      ///< friction force: along t (planar), magnitude (spatial) [N]
  /// coulomb_stick in stick: the F_t that keeps dv_t/dt = 0, before the
  /// clamp to mu F_n [N]
  double ft_required = 0.0;
};

/// Counters of a run, written by the integrator.
struct RunStats {
  long long steps = 0;              ///< RK4 steps of size h requested
  long long substeps = 0;           ///< RK4 evaluations taken, all kinds
  long long event_iterations = 0;   ///< of those, spent locating switches
  long long derivatives = 0;        ///< forwardDynamics evaluations, all callers
  long long mode_entries = 0;       ///< mode entries after located switches (a work unit each)
  int max_substeps_in_step = 0;     ///< worst step, in work units (sub-steps, trials, mode entries)
  long long impacts = 0;            ///< located contact onsets, every end
  long long separations = 0;        ///< located contact ends, every end
  std::array<long long, 2> impacts_joint{};  ///< onsets per gimbal joint (azimuth, elevation)
  std::array<double, 2> peak_fn_joint{};     ///< largest F_n at any end of each joint [N]
  std::array<double, 2> max_tilt_joint{};    ///< largest tilt angle gamma of each spatial joint [rad]
  /// per contact end (joint 1's first, a spatial joint's -L/2 end then +L/2):
  std::array<long long, 4> impacts_end{};    ///< onsets
  std::array<double, 4> peak_fn_end{};       ///< largest F_n [N]
  double last_onset_time = -1.0;    ///< [s]
  double peak_fn = 0.0, t_peak_fn = 0.0;        ///< [N], [s]
  double peak_contact = 0.0, t_peak_contact = 0.0;  ///< |F_n n + F_t t| [N], [s]
  double max_penetration = 0.0;     ///< [m]
  long long rejected_substeps = 0;  ///< adaptive: sub-steps taken back by error control
  long long forced_substeps = 0;    ///< adaptive: accepted at sim.substep_min above tolerance
  long long friction_switches = 0;  ///< coulomb_stick: located v_t reversals and stick/slip switches
  /// sub-steps retaken shorter because their RK4 stages met a contact that
  /// had ended again by the sub-step's end, or (fixed policy) a far
  /// sub-step reached the bearing
  long long straddle_retries = 0;
  /// fixed policy: shortest Hertz impact duration estimated at an onset [s]
  /// (0 = no impact yet)
  double min_impact_duration = 0.0;
};

template <class V>
struct Data {
  static constexpr int NV = V::NV, NQ = V::NQ, NJ = V::NJ;
  static constexpr int NE = V::NC > 0 ? V::NC : 1;  ///< contact ends kept (one, unused, without clearance)
  static constexpr bool kSpatial = V::kKind1 == ClearanceKind::Spatial || V::kKind2 == ClearanceKind::Spatial;
  using Contacts = std::array<ContactEval, NE>;
  using VecV = Eigen::Matrix<double, NV, 1>;
  using VecQ = Eigen::Matrix<double, NQ, 1>;
  using MatV = Eigen::Matrix<double, NV, NV>;

  explicit Data(const Model& model) { (void)model; }

  // ---- kinematics (kinematics.hpp) ----
  std::array<Transform, NJ> X{};  ///< chain body i relative to its parent
  Vec6 v_base = Vec6::Zero();     ///< base twist, base coords [rad/s, m/s]
  std::array<Vec6, NJ> v{};       ///< body twists, body coords

  // ---- inverse dynamics (rnea.hpp) ----
  Vec6 a_base = Vec6::Zero();
  std::array<Vec6, NJ> a{};       ///< spatial accelerations, body coords
  Vec6 f_base = Vec6::Zero();
  std::array<Vec6, NJ> f{};       ///< force transmitted by joint i to body i, body coords [N m, N]

  // ---- mass matrix (crba.hpp) ----
  MatV M = MatV::Zero();          ///< joint-space inertia [kg, kg m, kg m^2]
  MassFactor<V> mass;             ///< its factorisation (mass_factor.hpp)

  // ---- forward dynamics (forward_dynamics.hpp) ----
  VecV bias = VecV::Zero();       ///< C(q, v) v [N, N m]
  VecV tau = VecV::Zero();        ///< generalised applied forces incl. contact
  VecV vdot = VecV::Zero();
  VecQ qdot = VecQ::Zero();
  Contacts contact{};             ///< each contact end (V::NC), joint 1's first
  /// each spatial joint's contact in full (index: the joint), with its tilt
  std::array<SpatialContact, kSpatial ? 2 : 0> spatial{};

  // ---- integrator (integrator.hpp): scratch, and a cache that changes no result ----
  struct Deriv {
    VecQ qd = VecQ::Zero();
    VecV vd = VecV::Zero();
  };
  std::array<Deriv, 4> k{};       ///< RK4 stage derivatives (rk4.hpp)
  State<V> stage;                 ///< RK4 stage state
  State<V> trial, bracket_hi;     ///< end of the sub-step tried; past-the-switch end of the bracket
  Contacts contact_k1{};          ///< contact at the start of the last sub-step
  /// deepest penetration of each end over the last rk4() call's stages [m]
  std::array<double, NE> stage_delta_max{};
  RunStats stats;
  // Adaptive policy, first-same-as-last: f at the end of the last accepted
  // sub-step, reused as the next k1 while state and input are unchanged. A
  // pure cache (f depends on the state and input only): a fresh Data gives
  // the same bits, so State alone is the checkpoint.
  Deriv k_last;
  State<V> k_last_state;
  Vec2 k_last_tau = Vec2::Zero();
  bool k_last_valid = false;
  Contacts contact_last{};
};

}  // namespace gimbalsim
