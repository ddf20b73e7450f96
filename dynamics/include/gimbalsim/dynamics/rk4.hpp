// The classical fourth-order Runge-Kutta method and its embedded third-order
// companion, as coefficient tables, and one RK4 sub-step (docs/MODEL.md
// section 7.1). No allocation, no exception.
#pragma once

#include <array>
#include <cmath>

#include "gimbalsim/dynamics/forward_dynamics.hpp"

namespace gimbalsim {

/// Butcher tableau of classical RK4. Its matrix has only a sub-diagonal
/// (stage i+1 is evaluated at y + a[i] h k_i); the weights are given over a
/// common denominator, the form in which the step combines them.
struct Rk4Tableau {
  static constexpr double a[3] = {0.5, 0.5, 1.0};  ///< a(i+1, i)
  static constexpr double c[4] = {0.0, 0.5, 0.5, 1.0};
  static constexpr double b[4] = {1.0, 2.0, 2.0, 1.0};  ///< weights times kWeightDen
  static constexpr double kWeightDen = 6.0;
  /// Embedded third-order companion: weights (1, 2, 2, 0, 1) / 6 over
  /// k1..k4 and k5 = f(y_{n+1}) (first same as last). RK4 minus it is
  /// h (k4 - k5) / 6.
  static constexpr double b_embedded[5] = {1.0, 2.0, 2.0, 0.0, 1.0};
};
// The step writes k1 + 2 (k2 + k3) + k4 (that grouping fixes the rounding).
static_assert(Rk4Tableau::b[0] == 1.0 && Rk4Tableau::b[3] == 1.0 && Rk4Tableau::b[1] == Rk4Tableau::b[2]);
static_assert(Rk4Tableau::c[3] == Rk4Tableau::a[2] && Rk4Tableau::c[1] == Rk4Tableau::a[0]);

template <class V>
void evalDerivative(const Model& m, Data<V>& d, const State<V>& s, const Input& u, typename Data<V>::Deriv& k) {
  forwardDynamics(m, d, s, u);
  k.qd = d.qdot;
  k.vd = d.vdot;
}

/// One RK4 sub-step of length h from s into out, the input held over the
/// four stages, the quaternion renormalised at the end. With reuse_k1, d.k[0]
/// already holds f(s) (and d.contact_k1 its contact). Records in
/// d.stage_delta_max the deepest penetration the stages saw: a contact that
/// begins and ends inside the sub-step leaves both end points free.
template <class V>
void rk4(const Model& m, Data<V>& d, const State<V>& s, const Input& u, double h, State<V>& out,
         bool reuse_k1 = false) {
  using T = Rk4Tableau;
  auto& k = d.k;
  if (!reuse_k1) {
    evalDerivative(m, d, s, u, k[0]);
    if constexpr (V::kContact) d.contact_k1 = d.contact;
  }
  // deepest penetration of each end over the stages
  [[maybe_unused]] std::array<double, Data<V>::NE> stage_delta{};
  if constexpr (V::kContact) {
    for (int e = 0; e < V::NC; ++e) stage_delta[e] = d.contact_k1[e].delta;
  }
  State<V>& st = d.stage;
  st = s;
  for (int i = 1; i < 4; ++i) {
    st.t = s.t + T::c[i] * h;
    st.q = s.q + (T::a[i - 1] * h) * k[i - 1].qd;
    st.v = s.v + (T::a[i - 1] * h) * k[i - 1].vd;
    evalDerivative(m, d, st, u, k[i]);
    if constexpr (V::kContact) {
      for (int e = 0; e < V::NC; ++e) stage_delta[e] = std::fmax(stage_delta[e], d.contact[e].delta);
    }
  }
  if constexpr (V::kContact) d.stage_delta_max = stage_delta;
  out = s;
  out.t = s.t + h;
  out.q = s.q + (h / T::kWeightDen) * (k[0].qd + T::b[1] * (k[1].qd + k[2].qd) + k[3].qd);
  out.v = s.v + (h / T::kWeightDen) * (k[0].vd + T::b[1] * (k[1].vd + k[2].vd) + k[3].vd);
  if constexpr (V::kFloating) out.q.template segment<4>(3).normalize();
}

/// Local error of the sub-step of length h just taken into y, from the
/// embedded pair: h (k4 - k5) / 6 (k4 = d.k[3], k5 = f(y)); max over
/// coordinates of |err_i| / (1 + |y_i|) (SI units: m, rad, m/s, rad/s).
template <class V>
double embeddedError(const Data<V>& d, const typename Data<V>::Deriv& k5, const State<V>& y, double h) {
  using T = Rk4Tableau;
  static_assert(T::b[3] - T::b_embedded[3] == 1.0 && T::b_embedded[4] == 1.0);
  double e = 0.0;
  for (int i = 0; i < V::NQ; ++i) {
    e = std::fmax(e, std::fabs(d.k[3].qd(i) - k5.qd(i)) / (1.0 + std::fabs(y.q(i))));
  }
  for (int i = 0; i < V::NV; ++i) {
    e = std::fmax(e, std::fabs(d.k[3].vd(i) - k5.vd(i)) / (1.0 + std::fabs(y.v(i))));
  }
  return e * h / T::kWeightDen;
}

}  // namespace gimbalsim
