// The bearings' scene keys: contact.*, friction.* for both bearings,
// jointN.contact.*, jointN.friction.* for one joint's own, the old spellings
// contact1.*, friction1.*; how a joint's bearing follows from them and how
// each value is checked against the bearing it acts on (docs/scene_keys.md
// "The two bearings"). The journals' initial keys: journal_keys.cpp.
#include "bearing_keys.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace gimbalsim::scene_keys {

namespace {

using K = Keys<Scene>;
using SceneKey = Key<Scene>;

/// A bearing's keys: both joints' (contact.*, friction.*: Scene::both_joints)
/// or one joint's own (jointN.contact.*, jointN.friction.*: Model::bearing[N-1]),
/// which overrides the shared value key by key.
struct Bearing {
  int joint;             ///< 0, 1; -1 = the shared keys
  std::string contact;   ///< key prefix of the contact parameters
  std::string friction;  ///< key prefix of the friction parameters
  std::string whose;     ///< prefix of each meaning
  std::string alias_contact, alias_friction;  ///< old spellings ("" = none)

  ContactParams& of(Scene& s) const { return joint < 0 ? s.both_joints.bearing : s.model.bearing[joint]; }
  const ContactParams& of(const Scene& s) const { return joint < 0 ? s.both_joints.bearing : s.model.bearing[joint]; }
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

// [Pa] from soft rubber to diamond: 1e300 overflowed the Hertz stiffness into a NaN "in base_x".
const Check kYoungsModulus = interval('[', 1e3, 1e13, ']');

/// The contact and friction keys of a bearing.
std::vector<BearingKey> bearingKeys(const Bearing& b) {
  const auto contact = [b](auto& s) -> auto& { return b.of(s); };
  const std::string c = b.contact, f = b.friction, w = b.whose;
  using CP = ContactParams;
  return {
      bearingKey(b, K::number(c + "bearing_radius", "m", w + "R_i, bearing (on the parent body)",
                              // (pass 51) 1e12 m ran to NaN, its clearance lost to rounding: a gimbal's bearing
                              field(contact, &CP::bearing_radius), interval('(', 0, 10, ']')),
                 &CP::bearing_radius),
      bearingKey(b, K::number(c + "journal_radius", "m", w + "R_j, journal, < bearing_radius; or give " + c + "clearance",
                              field(contact, &CP::journal_radius),
                              greater(0).saying("journal radius (the bearing radius less any clearance given) must be > 0"))
                        .alternativeTo(c + "clearance"),
                 &CP::journal_radius),
      bearingKey(b, clearanceKey(b), &CP::clearance),
      bearingKey(b, K::number(c + "bearing_length", "m",
                              w + "spatial clearance: bearing length; contact at its two end planes (joint kind spatial)",
                              // Within 10 m: 1e300 m ran on to NaN "in base_x", naming no key.
                              field(contact, &CP::bearing_length), interval('(', 0.0, 10.0, ']')),
                 &CP::bearing_length),
      bearingKey(b, K::choice<RadiusMode>(c + "radius_mode", w + "R in the Hertz stiffness", field(contact, &CP::radius_mode),
                                          {{"paper", RadiusMode::Paper}, {"conformal", RadiusMode::Conformal}}),
                 &CP::radius_mode),
      bearingKey(b, K::number(c + "E_bearing", "Pa", w + "Young's modulus, bearing", field(contact, &CP::E_bearing),
                              kYoungsModulus),
                 &CP::E_bearing),
      bearingKey(b, K::number(c + "nu_bearing", "-", w + "Poisson's ratio, bearing", field(contact, &CP::nu_bearing),
                              interval('[', 0, 0.5, ')')),
                 &CP::nu_bearing),
      bearingKey(b, K::number(c + "E_journal", "Pa", w + "Young's modulus, journal", field(contact, &CP::E_journal),
                              kYoungsModulus),
                 &CP::E_journal),
      bearingKey(b, K::number(c + "nu_journal", "-", w + "Poisson's ratio, journal", field(contact, &CP::nu_journal),
                              interval('[', 0, 0.5, ')')),
                 &CP::nu_journal),
      bearingKey(b, K::number(c + "exponent", "-", w + "Hertz exponent n", field(contact, &CP::exponent),
                              interval('[', 1, 3, ']')),
                 &CP::exponent),
      bearingKey(b, K::number(c + "stiffness_scale", "-", w + "multiplies the Hertz stiffness K",
                              field(contact, &CP::stiffness_scale), interval('(', 0.0, 1e6, ']')),
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
      // at most 10, as a fault's friction_rise: a mu of 1e308 overflowed the friction force to Inf (pass 37)
      bearingKey(b, K::number(f + "mu", "-", w + "dynamic friction coefficient", field(contact, &CP::mu),
                              interval('[', 0, 10, ']')),
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

}  // namespace

/// The key that gave joint j's value of a bearing key ("contact." or
/// "friction." and the rest): its own if given, else the shared one (given
/// or its default).
std::string givenAs(const Given& g, int j, const std::string& section, const std::string& suffix) {
  const Bearing& b = j == 0 ? kJoint1 : kJoint2;
  const bool friction = section == "friction.";
  const std::string own = (friction ? b.friction : b.contact) + suffix;
  return g.has(own) ? own : section + suffix;
}

/// Whether the scene gave joint key `key` itself (Scene::BothJoints::own_keys).
bool ownKeyGiven(const Scene& s, const std::string& key) {
  const auto& given = s.both_joints.own_keys;
  return std::find(given.begin(), given.end(), key) != given.end();
}

namespace {

/// The own keys that override shared key k on every joint it would act on
/// (those with a bearing; a bearing length only on spatial ones), or "" if
/// one joint takes the shared value. A clearance and a journal radius give
/// one value: either own key overrides either shared one.
std::string everyJointOverrides(const Model& m, const Given& g, const BearingKey& k) {
  const bool radius = k.suffix == "clearance" || k.suffix == "journal_radius";
  const bool friction = k.key.key.rfind(kShared.friction, 0) == 0;
  std::string own_keys;
  for (int j = 0; j < 2; ++j) {
    const ClearanceKind kind = m.jointKind(j);
    if (kind == ClearanceKind::Ideal || (k.suffix == "bearing_length" && kind != ClearanceKind::Spatial)) continue;
    const Bearing& b = j == 0 ? kJoint1 : kJoint2;
    std::string own = (friction ? b.friction : b.contact) + k.suffix;
    if (radius) own = g.has(b.contact + "clearance") ? b.contact + "clearance" : b.contact + "journal_radius";
    if (!g.has(own)) return "";
    own_keys += (own_keys.empty() ? "" : ", ") + own;
  }
  return own_keys;
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
      // Both values named with the key that gave each: a joint's own bearing radius against the shared
      // journal radius was blamed on the journal's line alone, a key the user had not touched.
      const std::string bearing = joint < 0 ? b.contact + "bearing_radius" : givenAs(g, joint, "contact.", "bearing_radius");
      const std::string radius = by_clearance ? clearance : journal;  // the key that set the journal radius
      // At the joint's own key: its own bearing radius against the shared journal radius is the bearing's line.
      const auto is_shared = [](const std::string& key) { return key.rfind("contact.", 0) == 0; };
      g.refuse(joint >= 0 && is_shared(radius) && !is_shared(bearing) ? bearing : radius,
               "journal radius (" + formatNumber(cb.journal_radius) + " m, " + radius +
                   ") must be < bearing radius (" + formatNumber(cb.bearing_radius) + " m, " + bearing + ")");
    }
  }
  // Flores' chi at a tiny c_e makes the contact stiffer than any sub-step of a step's work bound resolves:
  // c_e = 1e-6 ended on sim.max_substeps at the paper scene's first impact, 1e-12 in NaN (pass 55).
  const bool damping_own = !shared || cb.damping != shared->damping || cb.restitution != shared->restitution;
  if (damping_own && cb.damping == DampingLaw::Flores && !(cb.restitution >= kFloresMinRestitution)) {
    g.refuse(joint < 0 ? b.contact + "restitution" : givenAs(g, joint, "contact.", "restitution"),
             "with contact.damping flores must be >= " + formatNumber(kFloresMinRestitution) + ", got " +
                 formatNumber(cb.restitution) + ": its factor 1 + 8 (1 - c_e) / (5 c_e) on the elastic force "
                 "needs more sub-steps than a step allows below it (docs/MODEL.md 5.2)");
  }
  if ((!shared || cb.v_a != shared->v_a || cb.v_b != shared->v_b) && !(cb.v_b > cb.v_a)) {
    const std::string vb = joint < 0 ? b.friction + "v_b" : givenAs(g, joint, "friction.", "v_b");
    const std::string va = joint < 0 ? b.friction + "v_a" : givenAs(g, joint, "friction.", "v_a");
    g.refuse(vb, "must be > " + va);
  }
}

/// A spatial bearing at least 4 clearances long: its journal then tilts at
/// most atan(2c/L) = 0.46 rad, where contact at the two end planes is the
/// model (a 1e-300 m bearing let a journal turn over, 3.13 rad).
void checkSpatialLength(const Scene& s, Given& g) {
  for (int j = 0; j < 2; ++j) {
    if (s.model.jointKind(j) != ClearanceKind::Spatial) continue;
    const ContactParams& b = s.model.bearing[j];
    const double c = b.bearing_radius - b.journal_radius;
    if (!(b.bearing_length >= kSpatialMinLengthInClearances * c)) {
      g.refuse(givenAs(g, j, "contact.", "bearing_length"),
               "a spatial bearing must be at least " + formatNumber(kSpatialMinLengthInClearances) +
                   " clearances long (joint " + std::to_string(j + 1) + ": " + formatNumber(b.bearing_length) +
                   " m against " + formatNumber(kSpatialMinLengthInClearances) + " x " + formatNumber(c) +
                   " m): its journal's tilt, up to atan(2c/L), must stay where contact at the two end planes holds");
    }
  }
}

}  // namespace

std::vector<Key<Scene>> bearingKeys() {
  std::vector<Key<Scene>> out;
  for (const Bearing* b : kBearings) {
    for (BearingKey& k : bearingKeys(*b)) {
      if (b->joint >= 0) {
        // A joint's value is checked and printed at its own key where it is
        // its own; the shared value at the shared key.
        const auto own = [same = k.same, j = b->joint](const Scene& s) {
          return !same(s.model.bearing[j], s.both_joints.bearing);
        };
        if (k.key.refusal) {
          k.key.refusal = [check = k.key.refusal, own](const Scene& s) { return own(s) ? check(s) : std::string(); };
        }
        k.key.present = [own, key = k.key.key](const Scene& s) { return own(s) || ownKeyGiven(s, key); };
      }
      out.push_back(std::move(k.key));
    }
  }
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

void validateBearings(const Scene& s, Given& g) {
  const Model& m = s.model;
  const IntegratorParams& p = m.integrator;
  // The shared bearing is checked as given; a joint's where it has clearance
  // and its own keys made it differ (named by the key that gave the value).
  checkBearing(s.both_joints.bearing, nullptr, -1, g);
  // Keys the joint kinds leave idle. A scene file keeps its shared bearing keys when its joints are set ideal
  // (an ideal twin): only a --set of one is said then.
  const bool any_spatial =
      m.jointKind(0) == ClearanceKind::Spatial || m.jointKind(1) == ClearanceKind::Spatial;
  for (const BearingKey& k : bearingKeys(kShared)) {
    if (!g.has(k.key.key)) continue;
    if (!m.hasClearance()) {
      g.idleIfSet(k.key.key, "no joint has clearance (structure.joint1, structure.joint2): no bearing, this value "
                             "does not act");
    } else if (k.suffix == "bearing_length" && !any_spatial) {
      g.idle(k.key.key, "no joint's bearing is spatial (structure.joint1, structure.joint2): no journal tilts, "
                        "this value does not act");
    } else if (const std::string own = everyJointOverrides(m, g, k); !own.empty()) {
      g.idleIfSet(k.key.key, "every joint it would act on gives its own (" + own + "): this value does not act");
    }
  }
  bool adaptive_refused = false;
  for (int j = 0; j < 2; ++j) {
    const ContactParams& cb = m.bearing[j];
    const std::string own_length = (j == 0 ? kJoint1 : kJoint2).contact + "bearing_length";
    if (m.jointKind(j) == ClearanceKind::Planar && g.has(own_length)) {
      g.idle(own_length, "joint " + std::to_string(j + 1) + "'s bearing is planar (structure.joint" +
                             std::to_string(j + 1) + "): its journal cannot tilt, this value does not act");
    }
    if (m.jointKind(j) == ClearanceKind::Ideal) {
      for (const BearingKey& k : jointBearingKeys(j)) {
        if (g.has(k.key.key)) {
          g.idle(k.key.key, "joint " + std::to_string(j + 1) + " is ideal (structure.joint" + std::to_string(j + 1) +
                                "): its bearing is not used");
        }
      }
      continue;
    }
    checkBearing(cb, &s.both_joints.bearing, j, g);
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
  idleFrictionKeys(s, g);
  checkInitialEcc(s, g);
  checkSpatialLength(s, g);
  checkInitialTilt(s, g);
}

/// Each joint's bearing: the shared values (contact.*, friction.*) but for
/// its own keys given; <prefix>clearance, when it gave the value, stands for
/// journal_radius = bearing_radius - c.
void deriveBearings(Scene& s, const Given& g) {
  const ContactParams& shared = s.both_joints.bearing;
  for (int j = 0; j < 2; ++j) {
    const Bearing& b = j == 0 ? kJoint1 : kJoint2;
    const ContactParams own = s.model.bearing[j];
    ContactParams& cb = s.model.bearing[j];
    cb = shared;
    for (const BearingKey& k : jointBearingKeys(j)) {
      if (!g.has(k.key.key)) continue;
      k.copy(cb, own);
      // a clearance is listed as the journal radius it sets (it has no value of its own)
      const bool clearance = k.key.key == b.contact + "clearance";
      s.both_joints.own_keys.push_back(clearance ? b.contact + "journal_radius" : k.key.key);
    }
    const bool own_journal = g.has(b.contact + "journal_radius");
    if (g.has(b.contact + "clearance") || (g.has(kShared.contact + "clearance") && !own_journal)) {
      setClearance(cb, cb.clearance);
    }
  }
  ContactParams& c = s.both_joints.bearing;
  if (g.has(kShared.contact + "clearance")) setClearance(c, c.clearance);
  deriveJournals(s, g);
}

}  // namespace gimbalsim::scene_keys
