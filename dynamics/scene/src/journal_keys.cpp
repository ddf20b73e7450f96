// Each journal's initial position keys: initial.ecc (both journals),
// initial.ecc1, initial.ecc2 and the spatial journals' initial.tilt1,
// initial.tilt2, with their checks against the bearing each acts on
// (docs/scene_keys.md "The two bearings"). The bearings' own keys: bearing_keys.cpp.
#include <cmath>

#include "bearing_keys.hpp"

namespace gimbalsim::scene_keys {

namespace {

using K = Keys<Scene>;
using SceneKey = Key<Scene>;

/// The initial eccentricity keys: both journals' (initial.ecc), then each one's.
const char* const kEccKeys[2] = {"initial.ecc1", "initial.ecc2"};

/// An initial eccentricity key: joint j's journal, or both (-1).
SceneKey eccKey(int joint, const char* key, const char* meaning) {
  if (joint < 0) return K::vector<2>(key, "m", meaning, [](auto& s) -> auto& { return s.both_joints.ecc; });
  SceneKey k = K::vector<2>(key, "m", meaning, [joint](auto& s) -> auto& { return s.run.initial.ecc[joint]; });
  k.present = [joint, key = std::string(key)](const Scene& s) {
    return s.run.initial.ecc[joint] != s.both_joints.ecc || ownKeyGiven(s, key);
  };
  return k;
}

/// Each spatial journal's initial tilt keys.
const char* const kTiltKeys[2] = {"initial.tilt1", "initial.tilt2"};

SceneKey tiltKey(int joint, const char* meaning) {
  return K::vector<2>(kTiltKeys[joint], "rad", meaning, [joint](auto& s) -> auto& { return s.run.initial.tilt[joint]; },
                      interval('[', -0.5, 0.5, ']'));
}

/// The eccentricity key that gave joint j's value: its own, else the shared one.
const char* eccKeyGiven(const Given& g, int j) { return g.has(kEccKeys[j]) ? kEccKeys[j] : "initial.ecc"; }

}  // namespace

/// Each journal's initial eccentricity against its own bearing. One that
/// cannot act (an ideal joint's) is accepted with a warning, not refused: a
/// scene's ideal twin (its joints set ideal, its values kept) must load.
void checkInitialEcc(const Scene& s, Given& g) {
  const Model& m = s.model;
  std::string warned;  // the shared key is named once
  for (int j = 0; j < 2; ++j) {
    const std::string key = eccKeyGiven(g, j);
    const Vec2& ecc = s.run.initial.ecc[j];
    const std::string joint = "joint " + std::to_string(j + 1);
    if (m.jointKind(j) != ClearanceKind::Ideal) {
      const double c = m.bearing[j].bearing_radius - m.bearing[j].journal_radius;
      // no clearance at all is the radii's refusal (checkBearing): said once, not again here
      if (c > 0.0 && ecc.norm() > c) g.refuse(key, "initial eccentricity exceeds the radial clearance of " + joint);
    } else if (ecc.norm() > 0.0 && key != warned && g.has(key) && (key != "initial.ecc" || !m.hasClearance())) {
      g.idle(key, m.hasClearance() ? joint + " is ideal (structure.joint" + std::to_string(j + 1) +
                                         "): its journal has no eccentricity, this value does not act"
                                   : std::string("no joint has clearance (structure.joint1, structure.joint2): no "
                                                 "journal starts off centre, this value does not act"));
      warned = key;
    }
  }
  // the shared value overridden on every joint with a bearing by the joint's own
  if (g.has("initial.ecc") && m.hasClearance()) {
    std::string own_keys;
    bool every = true;
    for (int j = 0; j < 2; ++j) {
      if (m.jointKind(j) == ClearanceKind::Ideal) continue;
      every = every && g.has(kEccKeys[j]);
      own_keys += std::string(own_keys.empty() ? "" : ", ") + kEccKeys[j];
    }
    if (every) {
      g.idleIfSet("initial.ecc",
                  "every joint with a bearing gives its own (" + own_keys + "): this value does not act");
    }
  }
}

/// Each spatial journal's initial tilt with its eccentricity: the journal's
/// axis must meet both end planes inside the clearance (docs/MODEL.md 2.7:
/// end s at p + s L/2 (tan(beta)/cos(alpha), -tan(alpha))), or the run would
/// start pressed deeper than any contact holds.
void checkInitialTilt(const Scene& s, Given& g) {
  const Model& m = s.model;
  for (int j = 0; j < 2; ++j) {
    const char* key = kTiltKeys[j];
    const Vec2& tilt = s.run.initial.tilt[j];
    if (!g.has(key) || tilt.norm() == 0.0) continue;
    const std::string joint = "joint " + std::to_string(j + 1);
    if (m.jointKind(j) != ClearanceKind::Spatial) {
      g.idle(key, joint + "'s bearing is not spatial (structure.joint" + std::to_string(j + 1) +
                      "): its journal cannot tilt, this value does not act");
      continue;
    }
    const ContactParams& b = m.bearing[j];
    const double c = b.bearing_radius - b.journal_radius;
    const Vec2& ecc = s.run.initial.ecc[j];
    if (!(c > 0.0) || ecc.norm() > c) continue;  // the radii's or the eccentricity's refusal, said once
    const Vec2 axis(std::tan(tilt.y()) / std::cos(tilt.x()), -std::tan(tilt.x()));
    for (const double end : {-1.0, 1.0}) {
      const double e = (ecc + end * 0.5 * b.bearing_length * axis).norm();
      if (!(e <= c)) {
        g.refuse(key, joint + "'s journal would start with its end at " + (end > 0 ? "+" : "-") + "L/2 " +
                          formatNumber(e) + " m off the bearing axis, beyond the clearance of " + formatNumber(c) +
                          " m (with " + eccKeyGiven(g, j) + " and " +
                          givenAs(g, j, "contact.", "bearing_length") + "): both ends must start inside the bearing");
        break;
      }
    }
  }
}

std::vector<Key<Scene>> journalKeys() {
  return {eccKey(-1, "initial.ecc", "both journals (unless a joint gives its own): initial eccentricity in the joint's "
                                    "plane (u1, u2), |ecc| <= its clearance"),
          eccKey(0, kEccKeys[0], "joint 1's journal only: initial eccentricity in its mid-plane (u1, u2)"),
          eccKey(1, kEccKeys[1], "joint 2's journal only: initial eccentricity in its mid-plane (u1, u2)"),
          tiltKey(0, "joint 1's journal (spatial only): initial tilt (alpha about u1, then beta), both ends "
                     "inside the clearance"),
          tiltKey(1, "joint 2's journal (spatial only): initial tilt (alpha about u1, then beta), both ends "
                     "inside the clearance")};
}

void deriveJournals(Scene& s, const Given& g) {
  for (int j = 0; j < 2; ++j) {
    if (!g.has(kEccKeys[j])) s.run.initial.ecc[j] = s.both_joints.ecc;
    else s.both_joints.own_keys.emplace_back(kEccKeys[j]);
  }
}

}  // namespace gimbalsim::scene_keys
