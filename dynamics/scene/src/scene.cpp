#include "gimbalsim/scene/scene.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <functional>
#include <cmath>

#include "gimbalsim/dynamics/observables.hpp"

namespace gimbalsim {

namespace {

using K = Keys<Scene>;
using SceneKey = Key<Scene>;

// The parts of a scene the keys bind to.
constexpr auto model = [](auto& s) -> auto& { return s.model; };
constexpr auto base = [](auto& s) -> auto& { return s.model.base; };
constexpr auto shaft1 = [](auto& s) -> auto& { return s.model.shaft1; };
constexpr auto shaft2 = [](auto& s) -> auto& { return s.model.shaft2; };
constexpr auto integ = [](auto& s) -> auto& { return s.model.integrator; };
constexpr auto run = [](auto& s) -> auto& { return s.run; };
constexpr auto initial = [](auto& s) -> auto& { return s.run.initial; };

/// A bearing's keys: both joints' (contact.*, friction.*: Scene::bearing_default)
/// or one joint's own (jointN.contact.*, jointN.friction.*: Model::bearing[N-1]),
/// which overrides the shared value key by key.
struct Bearing {
  int joint;             ///< 0, 1; -1 = the shared keys
  std::string contact;   ///< key prefix of the contact parameters
  std::string friction;  ///< key prefix of the friction parameters
  std::string whose;     ///< prefix of each meaning
  std::string alias_contact, alias_friction;  ///< old spellings ("" = none)

  ContactParams& of(Scene& s) const { return joint < 0 ? s.bearing_default : s.model.bearing[joint]; }
  const ContactParams& of(const Scene& s) const { return joint < 0 ? s.bearing_default : s.model.bearing[joint]; }
};
const Bearing kShared{-1, "contact.", "friction.", "both joints (unless a joint gives its own): ", "", ""};
const Bearing kJoint1{0, "joint1.contact.", "joint1.friction.", "joint 1 (azimuth) only: ", "contact1.", "friction1."};
const Bearing kJoint2{1, "joint2.contact.", "joint2.friction.", "joint 2 (elevation) only: ", "", ""};
const Bearing* const kBearings[] = {&kShared, &kJoint1, &kJoint2};

/// <prefix>clearance: another way to give <prefix>journal_radius (derived, no value of its own).
SceneKey clearanceKey(const Bearing& b) {
  SceneKey k(b.contact + "clearance", "number", "m", "",
             b.whose + "radial clearance c; sets journal_radius = bearing_radius - c (give this or journal_radius)");
  // Held in the derived field until every key is set (deriveBearings); finalize() recomputes it.
  k.set = [b](Scene& s, const YAML::Node& n) { b.of(s).clearance = asNumber(n); };
  k.alternative = b.contact + "journal_radius";
  return k;
}

/// A bearing key, how to copy its field from one bearing to another and
/// whether two bearings hold the same value there.
struct BearingKey {
  SceneKey key;
  std::string suffix;  ///< the key without its bearing prefix ("contact.mu" style: "mu")
  std::function<void(ContactParams& to, const ContactParams& from)> copy;
  std::function<bool(const ContactParams& a, const ContactParams& b)> same;
};

template <class M>
BearingKey bearingKey(const Bearing& b, SceneKey key, M ContactParams::*member) {
  const bool friction = key.key.rfind(b.friction, 0) == 0;
  std::string suffix = key.key.substr((friction ? b.friction : b.contact).size());
  return {std::move(key), std::move(suffix),
          [member](ContactParams& to, const ContactParams& from) { to.*member = from.*member; },
          [member](const ContactParams& x, const ContactParams& y) { return x.*member == y.*member; }};
}

/// The contact and friction keys of a bearing.
std::vector<BearingKey> bearingKeys(const Bearing& b) {
  const auto contact = [b](auto& s) -> auto& { return b.of(s); };
  const std::string c = b.contact, f = b.friction, w = b.whose;
  using CP = ContactParams;
  return {
      bearingKey(b, K::number(c + "bearing_radius", "m", w + "R_i, bearing (on the parent body)",
                              field(contact, &CP::bearing_radius), greater(0)),
                 &CP::bearing_radius),
      bearingKey(b, K::number(c + "journal_radius", "m", w + "R_j, journal, < bearing_radius; or give " + c + "clearance",
                              field(contact, &CP::journal_radius), greater(0).saying("journal radius must be > 0"))
                        .alternativeTo(c + "clearance"),
                 &CP::journal_radius),
      bearingKey(b, clearanceKey(b), &CP::clearance),
      bearingKey(b, K::number(c + "bearing_length", "m",
                              w + "spatial clearance: bearing length; contact at its two end planes (joint kind spatial)",
                              field(contact, &CP::bearing_length), greater(0)),
                 &CP::bearing_length),
      bearingKey(b, K::choice<RadiusMode>(c + "radius_mode", w + "R in the Hertz stiffness", field(contact, &CP::radius_mode),
                                          {{"paper", RadiusMode::Paper}, {"conformal", RadiusMode::Conformal}}),
                 &CP::radius_mode),
      bearingKey(b, K::number(c + "E_bearing", "Pa", w + "Young's modulus, bearing", field(contact, &CP::E_bearing),
                              greater(0)),
                 &CP::E_bearing),
      bearingKey(b, K::number(c + "nu_bearing", "-", w + "Poisson's ratio, bearing", field(contact, &CP::nu_bearing),
                              interval('[', 0, 0.5, ')')),
                 &CP::nu_bearing),
      bearingKey(b, K::number(c + "E_journal", "Pa", w + "Young's modulus, journal", field(contact, &CP::E_journal),
                              greater(0)),
                 &CP::E_journal),
      bearingKey(b, K::number(c + "nu_journal", "-", w + "Poisson's ratio, journal", field(contact, &CP::nu_journal),
                              interval('[', 0, 0.5, ')')),
                 &CP::nu_journal),
      bearingKey(b, K::number(c + "exponent", "-", w + "Hertz exponent n", field(contact, &CP::exponent),
                              interval('[', 1, 3, ']')),
                 &CP::exponent),
      bearingKey(b, K::number(c + "stiffness_scale", "-", w + "multiplies the Hertz stiffness K",
                              field(contact, &CP::stiffness_scale), greater(0)),
                 &CP::stiffness_scale),
      bearingKey(b, K::choice<DampingLaw>(c + "damping", w + "hysteresis damping law", field(contact, &CP::damping),
                                          {{"none", DampingLaw::None},
                                           {"hunt_crossley", DampingLaw::HuntCrossley},
                                           {"lankarani_nikravesh", DampingLaw::LankaraniNikravesh},
                                           {"flores", DampingLaw::Flores}}),
                 &CP::damping),
      bearingKey(b, K::number(c + "restitution", "-", w + "coefficient of restitution c_e",
                              field(contact, &CP::restitution), interval('(', 0, 1, ']')),
                 &CP::restitution),
      bearingKey(b, K::number(c + "v0_min", "m/s", w + "floor on the impact velocity v0 in the damping",
                              field(contact, &CP::v0_min), greater(0)),
                 &CP::v0_min),
      bearingKey(b, K::choice<FrictionLaw>(f + "law",
                                           w + "tangential force law (coulomb_stick: set-valued Coulomb, stick and "
                                               "slip located as events; a planar joint 2 with an ideal joint 1 only)",
                                           field(contact, &CP::friction),
                                           {{"none", FrictionLaw::None},
                                            {"coulomb", FrictionLaw::Coulomb},
                                            {"ambrosio", FrictionLaw::Ambrosio},
                                            {"coulomb_stick", FrictionLaw::CoulombStick}}),
                 &CP::friction),
      bearingKey(b, K::number(f + "mu", "-", w + "dynamic friction coefficient", field(contact, &CP::mu), atLeast(0)),
                 &CP::mu),
      bearingKey(b, K::number(f + "v_a", "m/s", w + "Ambrosio: no friction below this |v_t|", field(contact, &CP::v_a),
                              atLeast(0)),
                 &CP::v_a),
      bearingKey(b, K::number(f + "v_b", "m/s", w + "Ambrosio: full friction above this |v_t|, > " + f + "v_a",
                              field(contact, &CP::v_b), greater(0)),
                 &CP::v_b),
  };
}

/// Each joint's bearing keys (index: joint).
const std::vector<BearingKey>& jointBearingKeys(int joint) {
  static const std::vector<BearingKey> keys[2] = {bearingKeys(kJoint1), bearingKeys(kJoint2)};
  return keys[joint];
}

/// The key that gave joint j's value of a bearing key ("contact." or
/// "friction." and the rest): its own if given, else the shared one (given
/// or its default).
std::string givenAs(const Given& g, int j, const std::string& section, const std::string& suffix) {
  const Bearing& b = j == 0 ? kJoint1 : kJoint2;
  const bool friction = section == "friction.";
  const std::string own = (friction ? b.friction : b.contact) + suffix;
  return g.has(own) ? own : section + suffix;
}

/// The initial eccentricity keys: both journals' (initial.ecc), then each one's.
const char* const kEccKeys[2] = {"initial.ecc1", "initial.ecc2"};

/// An initial eccentricity key: joint j's journal, or both (-1).
SceneKey eccKey(int joint, const char* key, const char* meaning) {
  SceneKey k = K::vector<2>(key, "m", meaning, [joint](auto& s) -> auto& { return s.run.initial.ecc[joint < 0 ? 1 : joint]; });
  if (joint < 0) {
    k.set = [](Scene& s, const YAML::Node& n) { s.run.initial.ecc[0] = s.run.initial.ecc[1] = asVector<2>(n); };
  }
  return k;
}

std::vector<SceneKey> keys() {
  std::vector<SceneKey> out = {
      K::text("name", "scene name (default: the file name)", field(model, &Model::name)),
      K::choice<bool>("structure.base", "free-floating base or gimbal on a ground bench",
                      field(model, &Model::floating_base), {{"floating", true}, {"fixed", false}}),
      K::choice<ClearanceKind>("structure.joint1",
                               "azimuth joint model: ideal, planar clearance, or spatial clearance (the journal "
                               "may also tilt); its bearing is joint1.contact.*, joint1.friction.* over contact.*, friction.*",
                               field(model, &Model::joint1_kind),
                               {{"ideal", ClearanceKind::Ideal}, {"planar", ClearanceKind::Planar},
                                {"spatial", ClearanceKind::Spatial}}),
      K::choice<ClearanceKind>("structure.joint2",
                               "elevation joint model: ideal, clearance (planar, the paper's), planar (the same), or "
                               "spatial clearance (the journal may also tilt); its bearing is joint2.contact.*, joint2.friction.* over "
                               "contact.*, friction.*",
                               field(model, &Model::joint2_kind),
                               {{"ideal", ClearanceKind::Ideal}, {"clearance", ClearanceKind::Planar},
                                {"planar", ClearanceKind::Planar}, {"spatial", ClearanceKind::Spatial}}),
      K::number("base.mass", "kg", "base (satellite) mass", field(base, &BodyParams::mass),
                greater(0).saying("mass must be > 0")),
      K::inertia("base.inertia", "about the base CoM, base frame", field(base, &BodyParams::inertia)),
      K::number("shaft1.mass", "kg", "shaft 1 mass", field(shaft1, &BodyParams::mass),
                greater(0).saying("mass must be > 0")),
      K::vector<3>("shaft1.com", "m", "shaft 1 CoM from joint 1, shaft 1 frame", field(shaft1, &BodyParams::com)),
      K::inertia("shaft1.inertia", "about shaft 1's CoM, shaft 1 frame", field(shaft1, &BodyParams::inertia)),
      K::number("shaft2.mass", "kg", "shaft 2 + antenna mass", field(shaft2, &BodyParams::mass),
                greater(0).saying("mass must be > 0")),
      K::vector<3>("shaft2.com", "m", "shaft 2 CoM from joint 2 (journal centre), shaft 2 frame",
                   field(shaft2, &BodyParams::com)),
      K::inertia("shaft2.inertia", "about shaft 2's CoM, shaft 2 frame", field(shaft2, &BodyParams::inertia)),
      K::vector<3>("geometry.joint1_position", "m", "joint 1 from the base CoM, base frame",
                   field(model, &Model::r_J1_B_B)),
      K::vector<3>("geometry.joint1_axis", "-", "joint 1 (azimuth) axis, base frame", field(model, &Model::k1_B),
                   nonZero().saying("axis must be non-zero")),
      K::vector<3>("geometry.joint2_position", "m", "joint 2 (bearing centre) from joint 1, shaft 1 frame",
                   field(model, &Model::r_J2_S1_S1)),
      K::vector<3>("geometry.joint2_axis", "-", "joint 2 (elevation) axis, shaft 1 frame",
                   field(model, &Model::k2_S1), nonZero().saying("axis must be non-zero")),
      K::vector<3>("geometry.boresight", "-", "antenna boresight, shaft 2 frame", field(model, &Model::boresight_S2),
                   nonZero().saying("boresight must be non-zero")),
      K::number("torque.tau1", "N m", "constant joint 1 (azimuth) torque",
                [](auto& s) -> auto& { return s.run.torque(0); }),
      K::number("torque.tau2", "N m", "constant joint 2 (elevation) torque",
                [](auto& s) -> auto& { return s.run.torque(1); }),
      K::vector<2>("torque.limit", "N m", "motor torque limit per axis", field(run, &RunSpec::torque_limit),
                   greater(0)),
      K::number("initial.theta1", "rad", "initial joint 1 angle", field(initial, &InitialParams::theta1)),
      K::number("initial.theta2", "rad", "initial joint 2 angle", field(initial, &InitialParams::theta2)),
      K::number("initial.dtheta1", "rad/s", "initial joint 1 rate", field(initial, &InitialParams::dtheta1)),
      K::number("initial.dtheta2", "rad/s", "initial joint 2 rate", field(initial, &InitialParams::dtheta2)),
      eccKey(-1, "initial.ecc", "both journals (unless a joint gives its own): initial eccentricity in the joint's "
                                "plane (u1, u2), |ecc| <= its clearance"),
      eccKey(0, kEccKeys[0], "joint 1's journal only: initial eccentricity in its mid-plane (u1, u2)"),
      eccKey(1, kEccKeys[1], "joint 2's journal only: initial eccentricity in its mid-plane (u1, u2)"),
      K::number("sim.duration", "s", "simulated time", field(run, &RunSpec::duration), greater(0)),
      K::number("sim.step", "s", "RK4 step h", field(integ, &IntegratorParams::step), greater(0)),
      K::number("sim.output_interval", "s", "CSV row spacing, a multiple of sim.step",
                field(run, &RunSpec::output_interval), greater(0)),
      K::number("sim.substep", "s", "RK4 sub-step near and in contact, <= sim.step",
                field(integ, &IntegratorParams::substep), greater(0)),
      K::number("sim.event_tol", "s", "contact switch location tolerance, < sim.substep",
                field(integ, &IntegratorParams::event_tol), greater(0)),
      K::integer("sim.max_substeps", "-",
                 "work-unit cap per step (0 = automatic: step/substep + room for 4 located switches and one "
                 "retake; docs/MODEL.md 7.8)",
                 field(integ, &IntegratorParams::max_substeps), atLeast(0)),
      K::choice<SubstepPolicy>(
          "sim.substep_policy",
          "contact sub-steps: fixed sim.substep, or adaptive local error control to sim.substep_tol (adaptive "
          "is refused with plain friction.law=coulomb: use coulomb_stick or ambrosio)",
          field(integ, &IntegratorParams::substep_policy),
          {{"fixed", SubstepPolicy::Fixed}, {"adaptive", SubstepPolicy::Adaptive}}),
      K::number("sim.substep_tol", "-", "adaptive: local error per sub-step, max_i |err_i| / (1 + |y_i|)",
                field(integ, &IntegratorParams::substep_tol), interval('(', 0, 1, ')')),
      K::number("sim.substep_min", "s", "adaptive: smallest sub-step (taken even above tolerance, counted), <= sim.step",
                field(integ, &IntegratorParams::substep_min), greater(0)),
      K::number("sim.substep_max", "s", "adaptive: largest sub-step near contact (0 = sim.step), <= sim.step",
                field(integ, &IntegratorParams::substep_max), atLeast(0)),
      K::integer("sim.max_event_iters", "-", "switch location iteration cap",
                 field(integ, &IntegratorParams::max_event_iters), atLeast(1)),
      K::number("sim.velocity_limit", "rad/s, m/s", "any |v_i| above this stops the run as diverging",
                field(integ, &IntegratorParams::velocity_limit), greater(0)),
      K::number("sim.penetration_limit", "m", "penetration above this stops the run (0 = the clearance)",
                field(integ, &IntegratorParams::penetration_limit), atLeast(0)),
      K::number("sim.momentum_tol", "-",
                "relative momentum drift (floating base) that stops the run, checked at output rows (0 = off)",
                field(integ, &IntegratorParams::momentum_tol), atLeast(0)),
      K::number("sim.energy_tol", "-",
                "relative rise of kinetic + Hertz - torque work that stops the run, checked at output rows (0 = off)",
                field(integ, &IntegratorParams::energy_tol), atLeast(0)),
      K::number("sim.min_substeps_per_impact", "-",
                "fixed policy: an impact lasting fewer sub-steps than this (Hertz estimate) stops the run (0 = off)",
                field(integ, &IntegratorParams::min_substeps_per_impact), atLeast(0)),
  };
  // The bearings' keys after the geometry: the shared ones, then each joint's.
  const auto at = std::find_if(out.begin(), out.end(), [](const SceneKey& k) { return k.key == "torque.tau1"; });
  std::vector<SceneKey> bearings;
  for (const Bearing* b : kBearings) {
    for (BearingKey& k : bearingKeys(*b)) {
      if (b->joint >= 0 && k.key.refusal) {
        // A joint's value is checked at its own key where it is its own; the
        // shared value is checked at the shared key.
        k.key.refusal = [check = k.key.refusal, same = k.same, j = b->joint](const Scene& s) {
          return same(s.model.bearing[j], s.bearing_default) ? std::string() : check(s);
        };
      }
      bearings.push_back(std::move(k.key));
    }
  }
  out.insert(at, bearings.begin(), bearings.end());
  return out;
}

/// Old spellings of keys: joint 1's bearing was contact1.*, friction1.*.
std::vector<std::pair<std::string, std::string>> aliases() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const BearingKey& k : jointBearingKeys(0)) {
    const bool friction = k.key.key.rfind(kJoint1.friction, 0) == 0;
    out.emplace_back((friction ? kJoint1.alias_friction : kJoint1.alias_contact) + k.suffix, k.key.key);
  }
  return out;
}

/// A bearing's radii and Ambrosio speeds: the shared one (joint < 0), or
/// joint j's where its own keys made them differ from the shared ones.
void checkBearing(const ContactParams& cb, const ContactParams* shared, int joint, Given& g) {
  const Bearing& b = joint < 0 ? kShared : joint == 0 ? kJoint1 : kJoint2;
  const bool radii_own = !shared || cb.bearing_radius != shared->bearing_radius ||
                         cb.journal_radius != shared->journal_radius;
  if (radii_own) {
    // Named as given: <prefix>clearance stands for journal_radius when it was given instead.
    const std::string clearance = joint < 0 ? b.contact + "clearance" : givenAs(g, joint, "contact.", "clearance");
    const std::string journal = joint < 0 ? b.contact + "journal_radius" : givenAs(g, joint, "contact.", "journal_radius");
    const bool by_clearance = g.has(clearance) && !(joint >= 0 && g.has(b.contact + "journal_radius"));
    if (by_clearance && !(cb.bearing_radius - cb.journal_radius >= 0.0)) {
      g.refuse(clearance, "clearance must not be negative");
    } else if (!(cb.journal_radius < cb.bearing_radius)) {
      g.refuse(by_clearance ? clearance : journal,
               "journal radius (" + formatNumber(cb.journal_radius) + " m) must be < bearing radius (" +
                   formatNumber(cb.bearing_radius) + " m)");
    }
  }
  if ((!shared || cb.v_a != shared->v_a || cb.v_b != shared->v_b) && !(cb.v_b > cb.v_a)) {
    const std::string vb = joint < 0 ? b.friction + "v_b" : givenAs(g, joint, "friction.", "v_b");
    const std::string va = joint < 0 ? b.friction + "v_a" : givenAs(g, joint, "friction.", "v_a");
    g.refuse(vb, "must be > " + va);
  }
}

/// Each journal's initial eccentricity against its own bearing; one that
/// could never act (an ideal joint's) is refused unless zero.
void checkInitialEcc(const Scene& s, Given& g) {
  const Model& m = s.model;
  std::string refused;  // the shared key is named once
  for (int j = 0; j < 2; ++j) {
    const std::string key = g.has(kEccKeys[j]) ? kEccKeys[j] : "initial.ecc";
    const Vec2& ecc = s.run.initial.ecc[j];
    const std::string joint = "joint " + std::to_string(j + 1);
    if (m.jointKind(j) != ClearanceKind::Ideal) {
      const double c = m.bearing[j].bearing_radius - m.bearing[j].journal_radius;
      if (ecc.norm() > c) {
        g.refuse(key, "initial eccentricity exceeds the radial clearance of " + joint);
      }
    } else if (ecc.norm() > 0.0 && key == refused) {
      continue;
    } else if (ecc.norm() > 0.0 && !m.hasClearance()) {
      g.refuse(key, "no joint has clearance (structure.joint1, structure.joint2): no journal can start off centre");
      refused = key;
    } else if (ecc.norm() > 0.0 && key != "initial.ecc") {
      g.refuse(key, joint + " is ideal (structure.joint" + std::to_string(j + 1) +
                        "): its journal has no eccentricity; joint " + std::to_string(2 - j) + "'s is " +
                        kEccKeys[1 - j]);
    }
  }
}

/// Checks across keys (every key has passed its own check).
void validate(const Scene& s, Given& g) {
  const Model& m = s.model;
  const std::pair<const char*, const BodyParams*> bodies[] = {
      {"base.inertia", &m.base}, {"shaft1.inertia", &m.shaft1}, {"shaft2.inertia", &m.shaft2}};
  for (const auto& [key, b] : bodies) {
    const Vec3 p = Eigen::SelfAdjointEigenSolver<Mat3>(b->inertia).eigenvalues();
    for (int i = 0; i < 3; ++i) {
      if (p(i) > p((i + 1) % 3) + p((i + 2) % 3) * (1.0 + 1e-12)) {
        g.warn(key,
               "principal moments break the triangle inequality (no real rigid body has them); the equations "
               "stay well defined, continuing");
        break;
      }
    }
  }
  const IntegratorParams& p = m.integrator;
  // The shared bearing is checked as given; a joint's where it has clearance
  // and its own keys made it differ (named by the key that gave the value).
  checkBearing(s.bearing_default, nullptr, -1, g);
  bool adaptive_refused = false;
  for (int j = 0; j < 2; ++j) {
    const ContactParams& cb = m.bearing[j];
    if (m.jointKind(j) == ClearanceKind::Ideal) {
      for (const BearingKey& k : jointBearingKeys(j)) {
        if (g.has(k.key.key)) {
          g.warn(k.key.key, "joint " + std::to_string(j + 1) + " is ideal (structure.joint" + std::to_string(j + 1) +
                                "): its bearing is not used");
        }
      }
      continue;
    }
    checkBearing(cb, &s.bearing_default, j, g);
    const std::string law = givenAs(g, j, "friction.", "law");
    // Plain Coulomb's sign flip at v_t = 0 is a jump no local error control can
    // step over: every such run ended on sim.max_substeps. Refused, with the cure.
    if (cb.friction == FrictionLaw::Coulomb && cb.mu > 0.0 && p.substep_policy == SubstepPolicy::Adaptive &&
        !adaptive_refused) {
      adaptive_refused = true;
      g.refuse("sim.substep_policy", "adaptive cannot step over plain Coulomb friction's jump (" + law +
                                         "=coulomb): use " + law + "=coulomb_stick or ambrosio, or "
                                         "sim.substep_policy=fixed");
    }
    // Set-valued friction is built for one planar contact: a planar joint 2 with an ideal joint 1.
    const bool stick_shape = m.joint1_kind == ClearanceKind::Ideal && m.joint2_kind == ClearanceKind::Planar;
    if (cb.friction == FrictionLaw::CoulombStick && cb.mu > 0.0 && !stick_shape) {
      g.refuse(law, "coulomb_stick (set-valued friction) is built for a planar joint 2 with an ideal "
                    "joint 1 only: use coulomb or ambrosio with these joint kinds");
    }
  }
  checkInitialEcc(s, g);
  if (!(p.substep <= p.step)) g.refuse("sim.substep", "must be in (0, sim.step]");
  if (!(p.event_tol < p.substep)) g.refuse("sim.event_tol", "must be in (0, sim.substep)");
  if (!(p.substep_min <= p.step)) g.refuse("sim.substep_min", "must be in (0, sim.step]");
  if (!(p.substep_max <= p.step)) g.refuse("sim.substep_max", "must be in [0, sim.step]");
  // Derived counts (steps, rows, sub-step cap) must fit their integers, and
  // the CSV the disk: refused here, before anything runs (RunBounds).
  const double n_steps = s.run.duration / p.step;
  const double r = s.run.output_interval / p.step;
  // Durations and intervals are whole steps, or refused (wholeMultipleProblem): never rounded.
  if (!(n_steps <= RunBounds::kMaxSteps)) {
    g.refuse("sim.duration", "gives " + formatNumber(n_steps) + " steps of sim.step = " + formatNumber(p.step) +
                                 " s, more than " + formatNumber(RunBounds::kMaxSteps));
  } else if (const std::string why = wholeMultipleProblem(s.run.duration, p.step, "sim.step"); !why.empty()) {
    g.refuse("sim.duration", why);
  } else if (const std::string why_out = wholeMultipleProblem(s.run.output_interval, p.step, "sim.step");
             !(r <= RunBounds::kMaxSteps) || !why_out.empty()) {
    g.refuse("sim.output_interval", why_out.empty() ? "gives more than " + formatNumber(RunBounds::kMaxSteps) + " steps" : why_out);
  } else if (const double bytes = (std::floor(n_steps / std::round(r)) + 2) *
                                  outputColumns(s.model.joint1_kind, s.model.joint2_kind).count *
                                  RunBounds::kCsvValueBytes;
             !(bytes <= RunBounds::kMaxOutputBytes)) {
    g.refuse("sim.duration", "would write up to " + formatNumber(bytes) + " bytes of CSV (more than " +
                                 formatNumber(RunBounds::kMaxOutputBytes) + "): shorten it or raise sim.output_interval");
  }
  if (!(p.step / p.substep <= RunBounds::kMaxSubstepsPerStep)) {
    g.refuse("sim.substep", "gives " + formatNumber(p.step / p.substep) + " sub-steps per step, more than " +
                                formatNumber(RunBounds::kMaxSubstepsPerStep));
  }
  if (p.max_event_iters > RunBounds::kMaxEventIters) {
    g.refuse("sim.max_event_iters", "must be <= " + std::to_string(RunBounds::kMaxEventIters));
  }
}



/// Each joint's bearing: the shared values (contact.*, friction.*) but for
/// its own keys given; <prefix>clearance, when it gave the value, stands for
/// journal_radius = bearing_radius - c.
void deriveBearings(Scene& s, const Given& g) {
  const ContactParams& shared = s.bearing_default;
  for (int j = 0; j < 2; ++j) {
    const Bearing& b = j == 0 ? kJoint1 : kJoint2;
    const ContactParams own = s.model.bearing[j];
    ContactParams& cb = s.model.bearing[j];
    cb = shared;
    for (const BearingKey& k : jointBearingKeys(j)) {
      if (g.has(k.key.key)) k.copy(cb, own);
    }
    const bool own_journal = g.has(b.contact + "journal_radius");
    if (g.has(b.contact + "clearance") || (g.has(kShared.contact + "clearance") && !own_journal)) {
      setClearance(cb, cb.clearance);
    }
  }
  ContactParams& c = s.bearing_default;
  if (g.has(kShared.contact + "clearance")) setClearance(c, c.clearance);
}

}  // namespace

const KeyTable<Scene>& sceneTable() {
  static const KeyTable<Scene> table{
      {"a scene", "scene file", "`gimbalsim keys`", ""}, keys(), validate, deriveBearings, aliases()};
  return table;
}

std::vector<KeyInfo> sceneKeys() { return sceneTable().info(); }

void finishScene(Scene& sc, const std::string& origin, std::vector<std::string> warnings) {
  sc.warnings = std::move(warnings);
  sc.model.finalize();
  if (sc.model.name.empty()) sc.model.name = origin;
}

std::string readSceneFile(const std::string& path) {
  std::string text;
  std::string why;
  if (!readFile(path, text, &why)) throw SceneError(path + ": cannot open scene file: " + why);
  return text;
}

Scene loadSceneText(const std::string& yaml, const std::string& origin, const std::vector<std::string>& overrides) {
  std::vector<std::string> warnings;
  Scene out = loadKeys<SceneError>(sceneTable(), yaml, origin, overrides, &warnings);
  finishScene(out, origin, std::move(warnings));
  return out;
}

Scene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
  return loadSceneText(readSceneFile(path), path, overrides);
}

}  // namespace gimbalsim
