// Model: the constant description of a scene (pinocchio's Model / MuJoCo's
// mjModel). Built once from a scene file by loadScene() (scene.hpp), validated,
// then only ever passed as const Model&.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "gimbalsim/dynamics/spatial.hpp"

namespace gimbalsim {

enum class RadiusMode : std::uint8_t { Paper, Conformal };
enum class DampingLaw : std::uint8_t { None, HuntCrossley, LankaraniNikravesh, Flores };
/// CoulombStick: the set-valued Coulomb law (Filippov): slip direction kept as
/// a mode, v_t reversals and stick/slip switches located as events, and in
/// stick F_t is the force that keeps dv_t/dt = 0 while |F_t| <= mu F_n.
enum class FrictionLaw : std::uint8_t { None, Coulomb, Ambrosio, CoulombStick };
/// How the contact sub-step is chosen: Fixed = sim.substep; Adaptive = local
/// error control (embedded RK4/3 pair) to sim.substep_tol.
enum class SubstepPolicy : std::uint8_t { Fixed, Adaptive };
enum class JointKind : std::uint8_t { Revolute, Prismatic };
/// How a gimbal joint is modelled (docs/MODEL.md section 2): ideal, the
/// paper's planar clearance (journal centre in the plane normal to the axis),
/// or spatial clearance (that plane and a tilt of the journal axis).
enum class ClearanceKind : std::uint8_t { Ideal, Planar, Spatial };

/// Rigid body inertial parameters.
struct BodyParams {
  double mass = 1.0;                  ///< [kg]
  Vec3 com = Vec3::Zero();            ///< centre of mass in the body frame [m]
  Mat3 inertia = Mat3::Identity();    ///< about the centre of mass, body frame [kg m^2]
};

/// Journal-in-bearing contact of a clearance joint (docs/MODEL.md section 4).
struct ContactParams {
  double bearing_radius = 10.0e-3;    ///< R_i, on shaft 1 [m]
  double journal_radius = 9.5e-3;     ///< R_j, on shaft 2 [m]
  RadiusMode radius_mode = RadiusMode::Paper;
  double E_bearing = 166e9;           ///< Young's modulus [Pa]
  double nu_bearing = 0.28;           ///< Poisson's ratio [-]
  double E_journal = 177e9;           ///< [Pa]
  double nu_journal = 0.29;           ///< [-]
  double exponent = 1.5;              ///< Hertz exponent n [-]
  double stiffness_scale = 1.0;       ///< multiplies K (stress studies) [-]
  DampingLaw damping = DampingLaw::LankaraniNikravesh;
  double restitution = 0.95;          ///< c_e [-]
  double v0_min = 1.0e-4;             ///< floor on the impact velocity in D [m/s]
  FrictionLaw friction = FrictionLaw::Coulomb;
  double mu = 0.25;                   ///< dynamic friction coefficient [-]
  double v_a = 1.0e-4;                ///< Ambrosio: no friction below [m/s]
  double v_b = 1.0e-3;                ///< Ambrosio: full friction above [m/s]
  /// Spatial clearance: the bearing's length along its axis; contact is at
  /// its two end planes (docs/MODEL.md section 2.7) [m]
  double bearing_length = 0.05;

  /// Derived (deriveBearing): radial clearance c = R_i - R_j [m].
  double clearance = 0.5e-3;
  /// Derived: Hertz stiffness K [N/m^n] (paper eq. 11 with the chosen R).
  double K = 0.0;
  /// Derived: hysteresis factor chi with D = chi K delta^n / v0 [-].
  double chi = 0.0;
};

/// A spatial bearing at least this many clearances long: its journal then
/// tilts at most atan(2c/L) = 0.46 rad, where contact at the two end planes
/// is the model (the scene and the fault schedule's wear both hold to it).
inline constexpr double kSpatialMinLengthInClearances = 4.0;
/// The smallest c_e the flores law is run with: its chi = 8 (1 - c_e) / (5 c_e) multiplies the elastic force
/// by up to 1 + chi while the surfaces press (docs/MODEL.md 5.2).
inline constexpr double kFloresMinRestitution = 1e-4;

/// Numerical settings of the fixed-step integrator.
struct IntegratorParams {
  double step = 1.0e-3;               ///< RK4 step h [s]
  double substep = 2.0e-5;            ///< RK4 sub-step near and in contact [s]
  double event_tol = 1.0e-9;          ///< contact switch time tolerance [s]
  int max_substeps = 0;               ///< cap per step; 0 = automatic
  int max_event_iters = 60;           ///< cap on switch-location iterations
  double velocity_limit = 1.0e4;      ///< |v_i| above this is divergence [rad/s or m/s]
  double penetration_limit = 0.0;     ///< delta above this is divergence [m]; 0 = clearance
  /// Fixed policy: an impact whose Hertz duration estimate spans fewer
  /// sub-steps than this stops the run (sub-step too long for the contact);
  /// 0 = no check [-]
  double min_substeps_per_impact = 4.0;
  /// simulate(): relative drift of the linear or angular momentum (floating
  /// base) above this at an output row stops the run; 0 = no check [-]
  double momentum_tol = 1.0e-9;
  /// simulate(): rise of the energy balance (kinetic + Hertz - torque work)
  /// above this fraction of the energy scale stops the run (and any change,
  /// when no damping or friction can act); 0 = no check [-]
  double energy_tol = 1.0e-6;
  SubstepPolicy substep_policy = SubstepPolicy::Fixed;
  /// Adaptive: local error per sub-step, max over coordinates of
  /// |err_i| / (1 + |y_i|) (SI units: m, rad, m/s, rad/s) [-]
  double substep_tol = 1.0e-10;
  double substep_min = 1.0e-9;        ///< adaptive: smallest sub-step (accepted as is) [s]
  double substep_max = 0.0;           ///< adaptive: largest sub-step near contact; 0 = step [s]
};

/// The model's derivation of a bearing's terms from its parameters: c = R_i - R_j,
/// K (paper eq. 11, scaled), chi. Model::finalize and the bearing-wear fault use
/// it (the scene's checks and Python's provenance read c = R_i - R_j as well).
void deriveBearing(ContactParams& c);
/// A bearing with radial clearance c [m]: the journal is what changes
/// (R_j = R_i - c), then deriveBearing.
void setClearance(ContactParams& b, double c);

struct Model {
  std::string name;

  // ---- structure (picks the Variant) ----
  bool floating_base = true;
  ClearanceKind joint1_kind = ClearanceKind::Ideal;  ///< azimuth joint
  ClearanceKind joint2_kind = ClearanceKind::Ideal;  ///< elevation joint
  /// Any joint with clearance (a contact to resolve).
  bool hasClearance() const {
    return joint1_kind != ClearanceKind::Ideal || joint2_kind != ClearanceKind::Ideal;
  }

  // ---- bodies ----
  BodyParams base;    ///< base frame origin is the base centre of mass (com must be 0)
  BodyParams shaft1;  ///< frame origin at joint 1
  BodyParams shaft2;  ///< frame origin at joint 2 (the journal centre)

  // ---- geometry (all frames parallel to the inertial one at q = 0) ----
  Vec3 r_J1_B_B{0.0, 0.0, 0.5};     ///< joint 1 from base CoM, base frame [m]
  Vec3 k1_B{0.0, 0.0, 1.0};         ///< joint 1 axis, base frame (unit)
  Vec3 r_J2_S1_S1{0.0, 0.0, 1.0};   ///< joint 2 from joint 1, shaft 1 frame [m]
  Vec3 k2_S1{0.0, 1.0, 0.0};        ///< joint 2 axis, shaft 1 frame (unit)
  Vec3 boresight_S2{1.0, 0.0, 0.0}; ///< antenna boresight, shaft 2 frame (unit)

  /// Each joint's bearing: [0] joint 1 (azimuth), [1] joint 2 (elevation);
  /// read only where that joint has clearance.
  std::array<ContactParams, 2> bearing{};
  /// How the dynamics is integrated: read by step() itself, so it lives here
  /// and not in the run description (run_spec.hpp).
  IntegratorParams integrator;

  // ---- derived by finalize() ----
  /// Joint-1 plane basis in base coordinates: u1 x u2 = k1 (base x, base y
  /// for k1 = base z).
  Vec3 u1_B = Vec3::UnitX(), u2_B = Vec3::UnitY();
  /// Joint-2 plane basis in shaft 1 coordinates: u1 x u2 = k2.
  Vec3 u1_S1 = Vec3::UnitZ(), u2_S1 = Vec3::UnitX();
  /// Most 1-dof chain joints a scene can have (two spatial clearance joints).
  static constexpr int kMaxChain = 10;
  /// The 1-dof joints of the chain, one group per gimbal joint (variant.hpp:
  /// ideal [theta], planar [p_x, p_y, theta], spatial [p_x, p_y, alpha, beta,
  /// theta]); joint i connects chain body i-1 (or the base) to body i.
  struct ChainJoint {
    JointKind kind = JointKind::Revolute;
    Vec3 axis = Vec3::UnitZ();        ///< unit, parent frame (= child frame at q=0)
    Vec3 origin = Vec3::Zero();       ///< joint origin in the parent frame [m]
  };
  std::array<ChainJoint, kMaxChain> chain{};
  std::array<SpatialInertia, kMaxChain> I_chain{};  ///< chain body i about its origin, body coords
  SpatialInertia I_base;                    ///< base about its CoM, base coords

  /// The kind of joint j (0: azimuth, 1: elevation).
  ClearanceKind jointKind(int j) const { return j == 0 ? joint1_kind : joint2_kind; }

  /// Derives each bearing's terms (deriveBearing), the joint-plane bases and
  /// the chain. Call after any parameter change; loadScene() does.
  void finalize();

  /// Contact stiffness for a radius mode (paper eq. 11) [N/m^1.5].
  static double hertzStiffness(const ContactParams& c, RadiusMode mode);
};

}  // namespace gimbalsim
