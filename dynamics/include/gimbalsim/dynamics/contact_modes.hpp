// The discrete modes of the clearance joints, kept in State: each contact
// end's side (in_contact, with the impact velocity v0 of its current
// contact) and the
// slip/stick mode of friction.law coulomb_stick (friction_mode, vt_floor; the
// set-valued Coulomb law, docs/MODEL.md 6.4). When a mode must switch, and the
// mode to continue in just past a switch that event_locator.hpp located.
#pragma once

#include <cmath>

#include "gimbalsim/dynamics/forward_dynamics.hpp"

namespace gimbalsim {

/// coulomb_stick: has a friction switch happened between the segment's start
/// (whose mode x carries) and x? Slip: v_t changed sign against the mode.
/// Stick: the force needed to stick exceeds mu F_n. contact_at_x: d.contact
/// already holds forwardDynamics() at x (else it is evaluated here).
template <class V>
bool frictionSwitched(const Model& m, Data<V>& d, const State<V>& x, const Input& u, bool contact_at_x) {
  if constexpr (!V::kStick) {
    (void)m, (void)d, (void)x, (void)u, (void)contact_at_x;
    return false;
  } else {
    if (m.bearing[1].friction != FrictionLaw::CoulombStick || !x.in_contact[0]) return false;
    if (x.friction_mode != 0) return x.friction_mode * tangentialVelocity<V>(m, x.q, x.v) < x.vt_floor;
    if (!contact_at_x) forwardDynamics(m, d, x, u);
    return std::fabs(d.contact[0].ft_required) > m.bearing[1].mu * d.contact[0].fn;
  }
}

/// coulomb_stick: sets the friction mode to continue with from x, a state just
/// past a located switch (or a contact onset), x.friction_mode the mode before.
template <class V>
void enterFrictionMode(const Model& m, Data<V>& d, State<V>& x, const Input& u, bool onset) {
  const double vt = tangentialVelocity<V>(m, x.q, x.v);
  int mode = 0;
  if (onset && vt != 0.0) {
    mode = vt > 0.0 ? 1 : -1;
  } else {
    State<V>& probe = d.stage;
    probe = x;
    probe.friction_mode = 0;
    forwardDynamics(m, d, probe, u);
    mode = consistentFrictionMode(m, d);
    if (!onset && mode != 0 && mode == x.friction_mode) mode = 0;  // crossed within the tolerance
    if (!onset && mode == 0 && x.friction_mode == 0) mode = d.contact[0].ft_required > 0.0 ? -1 : 1;
  }
  x.friction_mode = mode;
  x.vt_floor = std::fmin(0.0, mode * vt);
}

/// Impact velocity v0 of end e at its onset state x [m/s]: the normal
/// relative velocity of the material points (planar: d(delta)/dt itself).
template <class V>
double onsetVelocity(const Model& m, Data<V>& d, const State<V>& x, const Input& u, int e) {
  if (V::kind(V::endJoint(e)) == ClearanceKind::Planar) return endGap<V>(m, e, x.q, x.v).rate;
  forwardDynamics(m, d, x, u);
  return d.contact[e].vn;
}

/// The state just past a located contact switch of end e: flips its contact
/// side and sets its contact memory (impact velocity v0 at an onset, the
/// friction mode); counts the impact or separation.
template <class V>
void enterContactSide(const Model& m, Data<V>& d, State<V>& x, const Input& u, int e) {
  x.in_contact[e] = !x.in_contact[e];
  if (x.in_contact[e]) {
    x.v0[e] = onsetVelocity(m, d, x, u, e);
    ++d.stats.impacts;
    ++d.stats.impacts_joint[V::endJoint(e)];
    ++d.stats.impacts_end[e];
    d.stats.last_onset_time = x.t;
    if constexpr (V::kStick) {
      if (m.bearing[1].friction == FrictionLaw::CoulombStick) enterFrictionMode(m, d, x, u, true);
    }
  } else {
    ++d.stats.separations;
    x.friction_mode = 0;
    x.vt_floor = 0.0;
  }
}

/// Just past a located contact switch: enters every end whose side the
/// state x is now past (usually one; two ends may switch within event_tol).
template <class V>
void enterSwitchedEnds(const Model& m, Data<V>& d, State<V>& x, const Input& u) {
  for (int e = 0; e < V::NC; ++e) {
    if ((endGap<V>(m, e, x.q, x.v).delta > 0.0) != x.in_contact[e]) enterContactSide(m, d, x, u, e);
  }
}

}  // namespace gimbalsim
