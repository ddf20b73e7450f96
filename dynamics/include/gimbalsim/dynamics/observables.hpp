// What a user reads off a state: world poses, momentum, energy, boresight,
// base Euler angles, the force joint 2 transmits. Not on the step hot path.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include "gimbalsim/dynamics/forward_dynamics.hpp"

namespace gimbalsim {

/// One output row. The order and names are the CSV header (kColumns).
struct Row {
  double t;                                    ///< [s]
  double base_x, base_y, base_z;               ///< base CoM, inertial [m]
  double base_vx, base_vy, base_vz;            ///< inertial [m/s]
  double base_ax, base_ay, base_az;            ///< inertial [m/s^2]
  double base_roll, base_pitch, base_yaw;      ///< Z-Y-X Euler angles [rad]
  double base_wx, base_wy, base_wz;            ///< angular velocity, base frame [rad/s]
  double base_dwx, base_dwy, base_dwz;         ///< angular acceleration, base frame [rad/s^2]
  double theta1, theta2;                       ///< joint angles [rad]
  double dtheta1, dtheta2;                     ///< [rad/s]
  double ddtheta1, ddtheta2;                   ///< [rad/s^2]
  // Each joint's bearing, joint 2's first (written for every scene; 0 where
  // ideal), joint 1's after the base columns (only when it has clearance):
  // eccentricity in its joint plane (u1, u2) (a spatial joint's: its
  // mid-plane), penetration (a spatial joint's: the deeper end's), normal
  // and friction force (summed over a spatial joint's ends).
  double ecc2_x, ecc2_y, ecc2;                 ///< eccentricity, joint-2 plane [m]
  double delta2;                               ///< penetration (0 if ideal) [m]
  double fn2, ft2;                             ///< contact normal, friction force [N]
  double joint2_force;                         ///< force joint 2 transmits [N]
  double bore_x, bore_y, bore_z;               ///< boresight unit vector, inertial
  double mom_px, mom_py, mom_pz;               ///< total linear momentum, inertial [N s]
  double mom_lx, mom_ly, mom_lz;               ///< total angular momentum about O [N m s]
  double energy;                               ///< total kinetic energy [J]
  double ecc1_x, ecc1_y, ecc1;                 ///< eccentricity, joint-1 mid-plane [m]
  double delta1;                               ///< deeper end's penetration [m]
  double fn1, ft1;                             ///< normal, friction force summed over its ends [N]
  // Spatial joints: the tilt angle gamma and each bearing end's penetration
  // and normal force, the end at -L/2 along k ("minus") and at +L/2 ("plus").
  double tilt1, delta1_minus, delta1_plus, fn1_minus, fn1_plus;  ///< [rad], [m], [m], [N], [N]
  double tilt2, delta2_minus, delta2_plus, fn2_minus, fn2_plus;  ///< [rad], [m], [m], [N], [N]
};
inline constexpr int kNumColumns = sizeof(Row) / sizeof(double);

/// One column: its name (the CSV header's, io::csvName adds the unit), its
/// unit ("-": none) and the Row member it reads.
struct RowField {
  const char* name;
  const char* unit;
  double Row::*member;
};

/// Every column, in Row's order: the one list a new column is added to. The
/// names, the units, the firmware's truth (sampleTruth, by name) and the
/// Python package's columns follow from it; tests/base/csv_format_test.cpp checks
/// that it covers Row member by member, in order.
inline constexpr std::array<RowField, kNumColumns> kRowFields = {{
    {"t", "s", &Row::t},
    {"base_x", "m", &Row::base_x},
    {"base_y", "m", &Row::base_y},
    {"base_z", "m", &Row::base_z},
    {"base_vx", "m/s", &Row::base_vx},
    {"base_vy", "m/s", &Row::base_vy},
    {"base_vz", "m/s", &Row::base_vz},
    {"base_ax", "m/s^2", &Row::base_ax},
    {"base_ay", "m/s^2", &Row::base_ay},
    {"base_az", "m/s^2", &Row::base_az},
    {"base_roll", "rad", &Row::base_roll},
    {"base_pitch", "rad", &Row::base_pitch},
    {"base_yaw", "rad", &Row::base_yaw},
    {"base_wx", "rad/s", &Row::base_wx},
    {"base_wy", "rad/s", &Row::base_wy},
    {"base_wz", "rad/s", &Row::base_wz},
    {"base_dwx", "rad/s^2", &Row::base_dwx},
    {"base_dwy", "rad/s^2", &Row::base_dwy},
    {"base_dwz", "rad/s^2", &Row::base_dwz},
    {"theta1", "rad", &Row::theta1},
    {"theta2", "rad", &Row::theta2},
    {"dtheta1", "rad/s", &Row::dtheta1},
    {"dtheta2", "rad/s", &Row::dtheta2},
    {"ddtheta1", "rad/s^2", &Row::ddtheta1},
    {"ddtheta2", "rad/s^2", &Row::ddtheta2},
    {"ecc2_x", "m", &Row::ecc2_x},
    {"ecc2_y", "m", &Row::ecc2_y},
    {"ecc2", "m", &Row::ecc2},
    {"delta2", "m", &Row::delta2},
    {"fn2", "N", &Row::fn2},
    {"ft2", "N", &Row::ft2},
    {"joint2_force", "N", &Row::joint2_force},
    {"bore_x", "-", &Row::bore_x},
    {"bore_y", "-", &Row::bore_y},
    {"bore_z", "-", &Row::bore_z},
    {"mom_px", "N s", &Row::mom_px},
    {"mom_py", "N s", &Row::mom_py},
    {"mom_pz", "N s", &Row::mom_pz},
    {"mom_lx", "N m s", &Row::mom_lx},
    {"mom_ly", "N m s", &Row::mom_ly},
    {"mom_lz", "N m s", &Row::mom_lz},
    {"energy", "J", &Row::energy},
    {"ecc1_x", "m", &Row::ecc1_x},
    {"ecc1_y", "m", &Row::ecc1_y},
    {"ecc1", "m", &Row::ecc1},
    {"delta1", "m", &Row::delta1},
    {"fn1", "N", &Row::fn1},
    {"ft1", "N", &Row::ft1},
    {"tilt1", "rad", &Row::tilt1},
    {"delta1_minus", "m", &Row::delta1_minus},
    {"delta1_plus", "m", &Row::delta1_plus},
    {"fn1_minus", "N", &Row::fn1_minus},
    {"fn1_plus", "N", &Row::fn1_plus},
    {"tilt2", "rad", &Row::tilt2},
    {"delta2_minus", "m", &Row::delta2_minus},
    {"delta2_plus", "m", &Row::delta2_plus},
    {"fn2_minus", "N", &Row::fn2_minus},
    {"fn2_plus", "N", &Row::fn2_plus},
}};

/// The column names and units, in Row's order (from kRowFields).
inline constexpr std::array<const char*, kNumColumns> kColumns = [] {
  std::array<const char*, kNumColumns> a{};
  for (int i = 0; i < kNumColumns; ++i) a[i] = kRowFields[i].name;
  return a;
}();
inline constexpr std::array<const char*, kNumColumns> kColumnUnits = [] {
  std::array<const char*, kNumColumns> a{};
  for (int i = 0; i < kNumColumns; ++i) a[i] = kRowFields[i].unit;
  return a;
}();

/// The index of column `name` in Row (-1: none).
constexpr int columnIndex(std::string_view name) {
  for (int i = 0; i < kNumColumns; ++i) {
    if (name == kRowFields[i].name) return i;
  }
  return -1;
}

/// The row's columns as one array (Row is kNumColumns doubles, in kRowFields' order).
inline const double* rowData(const Row& r) { return &r.t; }

/// Columns a run writes: the first kBaseColumns always (an ideal joint 2's
/// ecc2 .. ft2 are 0), joint 1's six when it has clearance, the five tilt and
/// per-end columns of each spatial joint. A row keeps every column (0 where
/// the shape has none); the CSV and the Python package show this set.
inline constexpr int kBaseColumns = columnIndex("ecc1_x");
static_assert(kColumns[kBaseColumns - 1] == std::string_view("energy"), "base columns end at energy");
struct ColumnSet {
  std::array<int, kNumColumns> index{};  ///< into Row / kColumns, ascending
  int count = 0;
};
constexpr ColumnSet outputColumns(ClearanceKind joint1, ClearanceKind joint2) {
  ColumnSet c;
  auto take = [&c](int first, int n) {
    for (int i = first; i < first + n; ++i) c.index[c.count++] = i;
  };
  take(0, kBaseColumns);
  if (joint1 != ClearanceKind::Ideal) take(kBaseColumns, 6);                  // ecc1_x .. ft1
  if (joint1 == ClearanceKind::Spatial) take(columnIndex("tilt1"), 5);       // tilt1 .. fn1_plus
  if (joint2 == ClearanceKind::Spatial) take(columnIndex("tilt2"), 5);       // tilt2 .. fn2_plus
  return c;
}
/// No NaN or Inf in any column.
inline bool rowFinite(const Row& r) {
  return std::all_of(rowData(r), rowData(r) + kNumColumns, [](double x) { return std::isfinite(x); });
}

/// World pose of every body (base, then chain bodies).
template <class V>
struct WorldPoses {
  Mat3 R_WB = Mat3::Identity();
  Vec3 p_WB = Vec3::Zero();
  std::array<Mat3, V::NJ> R{};
  std::array<Vec3, V::NJ> p{};
};

/// Needs kinematics() at s.
template <class V>
WorldPoses<V> worldPoses(const Data<V>& d, const State<V>& s) {
  WorldPoses<V> w;
  if constexpr (V::kFloating) {
    w.R_WB = Quat(s.q(3), s.q(4), s.q(5), s.q(6)).normalized().toRotationMatrix();
    w.p_WB = s.q.template head<3>();
  }
  Mat3 R = w.R_WB;
  Vec3 p = w.p_WB;
  for (int i = 0; i < V::NJ; ++i) {
    p = p + R * d.X[i].r_PC_P;
    R = R * d.X[i].R_PC;
    w.R[i] = R;
    w.p[i] = p;
  }
  return w;
}

struct Momentum {
  Vec3 linear = Vec3::Zero();   ///< [N s], inertial
  Vec3 angular = Vec3::Zero();  ///< about the inertial origin [N m s]
  double energy = 0.0;          ///< kinetic [J]
  double scale = 0.0;           ///< sum of |angular momentum| of the bodies: drift reference [N m s]
  double scale_linear = 0.0;    ///< sum of |linear momentum| of the bodies [N s]
};

/// Needs kinematics() at s.
template <class V>
Momentum momentum(const Model& m, const Data<V>& d, const State<V>& s) {
  const WorldPoses<V> w = worldPoses(d, s);
  Momentum out;
  auto add = [&](const SpatialInertia& I, const Vec6& v, const Mat3& R, const Vec3& p) {
    const Vec6 h = I * v;  // spatial momentum about the body origin, body coords
    const Vec3 lin = R * h.template tail<3>();
    const Vec3 ang = R * h.template head<3>() + p.cross(lin);
    out.linear += lin;
    out.angular += ang;
    out.energy += 0.5 * v.dot(h);
    out.scale += ang.norm();
    out.scale_linear += lin.norm();
  };
  if constexpr (V::kFloating) add(m.I_base, d.v_base, w.R_WB, w.p_WB);
  for (int i = 0; i < V::NJ; ++i) add(m.I_chain[i], d.v[i], w.R[i], w.p[i]);
  return out;
}

/// Antenna boresight in the inertial frame; needs kinematics() at s.
template <class V>
Vec3 boresight(const Model& m, const Data<V>& d, const State<V>& s) {
  return worldPoses(d, s).R[V::NJ - 1] * m.boresight_S2;
}

/// Z-Y-X (yaw, pitch, roll) Euler angles of R: returns (roll, pitch, yaw) [rad].
inline Vec3 eulerZYX(const Mat3& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  return {std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0))};
}

/// Fills an output row at s (one forward-dynamics evaluation plus one RNEA).
template <class V>
Row observe(const Model& m, Data<V>& d, const State<V>& s, const Input& u) {
  constexpr int QJ = State<V>::QJ, NB = V::NB, NJ = V::NJ;
  forwardDynamics(m, d, s, u);
  Row r{};
  r.t = s.t;
  const WorldPoses<V> w = worldPoses(d, s);
  if constexpr (V::kFloating) {
    const Vec3 wB = s.v.template head<3>(), vB = s.v.template segment<3>(3);
    const Vec3 p = w.p_WB, vel = w.R_WB * vB;
    const Vec3 acc = w.R_WB * (d.vdot.template segment<3>(3) + wB.cross(vB));
    const Vec3 eul = eulerZYX(w.R_WB);
    r.base_x = p.x(), r.base_y = p.y(), r.base_z = p.z();
    r.base_vx = vel.x(), r.base_vy = vel.y(), r.base_vz = vel.z();
    r.base_ax = acc.x(), r.base_ay = acc.y(), r.base_az = acc.z();
    r.base_roll = eul.x(), r.base_pitch = eul.y(), r.base_yaw = eul.z();
    r.base_wx = wB.x(), r.base_wy = wB.y(), r.base_wz = wB.z();
    r.base_dwx = d.vdot(0), r.base_dwy = d.vdot(1), r.base_dwz = d.vdot(2);
  }
  r.theta1 = s.q(QJ + V::theta(0)), r.theta2 = s.q(QJ + V::theta(1));
  r.dtheta1 = s.v(NB + V::theta(0)), r.dtheta2 = s.v(NB + V::theta(1));
  r.ddtheta1 = d.vdot(NB + V::theta(0)), r.ddtheta2 = d.vdot(NB + V::theta(1));
  if constexpr (V::kKind2 == ClearanceKind::Planar) {
    const ContactEval& c = d.contact[V::firstEnd(1)];
    r.ecc2_x = s.q(PlanarGroup<V, 1>::QE), r.ecc2_y = s.q(PlanarGroup<V, 1>::QE + 1), r.ecc2 = c.e;
    r.delta2 = c.delta;
    r.fn2 = c.fn, r.ft2 = c.ft;
    r.joint2_force = std::hypot(c.fn, c.ft);
  } else if constexpr (V::kKind2 == ClearanceKind::Spatial) {
    // Mid-plane eccentricity; the deeper end's penetration; both ends' forces.
    const int qg = QJ + V::G2;
    const SpatialContact& sc = d.spatial[1];
    r.ecc2_x = s.q(qg), r.ecc2_y = s.q(qg + 1), r.ecc2 = std::hypot(r.ecc2_x, r.ecc2_y);
    r.delta2 = std::fmax(sc.end[0].delta, sc.end[1].delta);
    r.fn2 = sc.end[0].fn + sc.end[1].fn;
    r.ft2 = sc.end[0].ft_B.norm() + sc.end[1].ft_B.norm();
    Vec3 F = Vec3::Zero();
    for (const SpatialEnd& e : sc.end) F += -e.fn * e.n_B + e.ft_B;
    r.joint2_force = F.norm();
  }
  if constexpr (V::kKind1 == ClearanceKind::Planar) {
    const ContactEval& c = d.contact[V::firstEnd(0)];
    r.ecc1_x = s.q(PlanarGroup<V, 0>::QE), r.ecc1_y = s.q(PlanarGroup<V, 0>::QE + 1), r.ecc1 = c.e;
    r.delta1 = c.delta;
    r.fn1 = c.fn, r.ft1 = c.ft;
  } else if constexpr (V::kKind1 == ClearanceKind::Spatial) {
    const SpatialContact& sc = d.spatial[0];
    r.ecc1_x = s.q(QJ + V::G1), r.ecc1_y = s.q(QJ + V::G1 + 1), r.ecc1 = std::hypot(r.ecc1_x, r.ecc1_y);
    r.delta1 = std::fmax(sc.end[0].delta, sc.end[1].delta);
    r.fn1 = sc.end[0].fn + sc.end[1].fn;
    r.ft1 = sc.end[0].ft_B.norm() + sc.end[1].ft_B.norm();
    r.tilt1 = sc.gamma;
    r.delta1_minus = sc.end[0].delta, r.delta1_plus = sc.end[1].delta;
    r.fn1_minus = sc.end[0].fn, r.fn1_plus = sc.end[1].fn;
  }
  if constexpr (V::kKind2 == ClearanceKind::Spatial) {
    const SpatialContact& sc = d.spatial[1];
    r.tilt2 = sc.gamma;
    r.delta2_minus = sc.end[0].delta, r.delta2_plus = sc.end[1].delta;
    r.fn2_minus = sc.end[0].fn, r.fn2_plus = sc.end[1].fn;
  }
  const Vec3 b = w.R[NJ - 1] * m.boresight_S2;
  r.bore_x = b.x(), r.bore_y = b.y(), r.bore_z = b.z();
  const Momentum h = momentum(m, d, s);
  r.mom_px = h.linear.x(), r.mom_py = h.linear.y(), r.mom_pz = h.linear.z();
  r.mom_lx = h.angular.x(), r.mom_ly = h.angular.y(), r.mom_lz = h.angular.z();
  r.energy = h.energy;
  if constexpr (V::kKind2 == ClearanceKind::Ideal) {
    // Ideal joint: the constraint force joint 2 transmits, from the RNEA at
    // the actual acceleration (its moment part holds the torque couple).
    typename Data<V>::VecV tau;
    const typename Data<V>::VecV vdot = d.vdot;
    rnea(m, d, s.v, vdot, tau);
    r.joint2_force = d.f[NJ - 1].template tail<3>().norm();
  }
  return r;
}

// Compiled once per shape in dynamics/src/shapes.inc.
#ifndef GIMBALSIM_COMPILING_SHAPES
#define GIMBALSIM_EXTERN_OBSERVE(FL, K1, K2, FR)                                                  \
  extern template Row observe<GIMBALSIM_SHAPE(FL, K1, K2, FR)>(                                 \
      const Model&, Data<GIMBALSIM_SHAPE(FL, K1, K2, FR)>&, const State<GIMBALSIM_SHAPE(FL, K1, K2, FR)>&, \
      const Input&);
GIMBALSIM_FOR_EACH_SHAPE(GIMBALSIM_EXTERN_OBSERVE)
#undef GIMBALSIM_EXTERN_OBSERVE
#endif

}  // namespace gimbalsim
