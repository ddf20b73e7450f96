#include "gimbalsim/scene/scene.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <functional>
#include <cmath>

#include "bearing_keys.hpp"
#include "gimbalsim/dynamics/observables.hpp"
#include "gimbalsim/dynamics/simulator.hpp"

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

// [N m] a joint torque or its limit: within what any gimbal motor gives,
// far from overflow in the mass matrix's solve (inertias reach 1e12).
const Check kTorque = interval('[', -1e6, 1e6, ']');
// [rad], [rad/s] a joint's start: 1e300 rad/s overflowed at t = 0 with no key named.
const Check kJointAngle = interval('[', -1e3, 1e3, ']');
const Check kJointRate = interval('[', -1e3, 1e3, ']');

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
                bodyMass()),
      K::inertia("base.inertia", "about the base CoM, base frame", field(base, &BodyParams::inertia)),
      K::number("shaft1.mass", "kg", "shaft 1 mass", field(shaft1, &BodyParams::mass),
                bodyMass()),
      K::vector<3>("shaft1.com", "m", "shaft 1 CoM from joint 1, shaft 1 frame", field(shaft1, &BodyParams::com),
                   bodyOffset()),
      K::inertia("shaft1.inertia", "about shaft 1's CoM, shaft 1 frame", field(shaft1, &BodyParams::inertia)),
      K::number("shaft2.mass", "kg", "shaft 2 + antenna mass", field(shaft2, &BodyParams::mass),
                bodyMass()),
      K::vector<3>("shaft2.com", "m", "shaft 2 CoM from joint 2 (journal centre), shaft 2 frame",
                   field(shaft2, &BodyParams::com), bodyOffset()),
      K::inertia("shaft2.inertia", "about shaft 2's CoM, shaft 2 frame", field(shaft2, &BodyParams::inertia)),
      K::vector<3>("geometry.joint1_position", "m", "joint 1 from the base CoM, base frame",
                   field(model, &Model::r_J1_B_B), bodyOffset()),
      K::vector<3>("geometry.joint1_axis", "-", "joint 1 (azimuth) axis, base frame", field(model, &Model::k1_B),
                   nonZero().saying("axis must be of length at least 1e-12, each component within 1e12")),
      K::vector<3>("geometry.joint2_position", "m", "joint 2 (bearing centre) from joint 1, shaft 1 frame",
                   field(model, &Model::r_J2_S1_S1), bodyOffset()),
      K::vector<3>("geometry.joint2_axis", "-", "joint 2 (elevation) axis, shaft 1 frame",
                   field(model, &Model::k2_S1),
                   nonZero().saying("axis must be of length at least 1e-12, each component within 1e12")),
      K::vector<3>("geometry.boresight", "-", "antenna boresight, shaft 2 frame", field(model, &Model::boresight_S2),
                   nonZero().saying("boresight must be of length at least 1e-12, each component within 1e12")),
      K::number("torque.tau1", "N m", "constant joint 1 (azimuth) torque",
                [](auto& s) -> auto& { return s.run.torque(0); }, kTorque),
      K::number("torque.tau2", "N m", "constant joint 2 (elevation) torque",
                [](auto& s) -> auto& { return s.run.torque(1); }, kTorque),
      K::vector<2>("torque.limit", "N m", "motor torque limit per axis", field(run, &RunSpec::torque_limit),
                   interval('(', 0.0, 1e6, ']')),
      K::number("initial.theta1", "rad", "initial joint 1 angle", field(initial, &InitialParams::theta1), kJointAngle),
      K::number("initial.theta2", "rad", "initial joint 2 angle", field(initial, &InitialParams::theta2), kJointAngle),
      K::number("initial.dtheta1", "rad/s", "initial joint 1 rate", field(initial, &InitialParams::dtheta1), kJointRate),
      K::number("initial.dtheta2", "rad/s", "initial joint 2 rate", field(initial, &InitialParams::dtheta2), kJointRate),
      K::number("sim.duration", "s", "simulated time", field(run, &RunSpec::duration), greater(0)),
      K::number("sim.step", "s", "RK4 step h", field(integ, &IntegratorParams::step), greater(0)),
      K::number("sim.output_interval", "s", "CSV row spacing, a multiple of sim.step",
                field(run, &RunSpec::output_interval), greater(0)),
      K::number("sim.substep", "s", "RK4 sub-step near and in contact, <= sim.step",
                field(integ, &IntegratorParams::substep), greater(0)),
      K::number("sim.event_tol", "s",
                "contact switch location tolerance, < sim.substep, no finer than time at the run's end",
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
  const std::vector<SceneKey> bearings = scene_keys::bearingKeys();
  out.insert(at, bearings.begin(), bearings.end());
  // The journals' initial eccentricities and tilts after the joint angles and rates.
  const auto journal_at =
      std::find_if(out.begin(), out.end(), [](const SceneKey& k) { return k.key == "sim.duration"; });
  const std::vector<SceneKey> journal = scene_keys::journalKeys();
  out.insert(journal_at, journal.begin(), journal.end());
  return out;
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
  // A fixed base never moves: its mass and inertia never enter, joint 1's place on it only shifts the whole
  // gimbal (no gravity) and no momentum drift is checked (pass 91: a --set of them ran with no word; the Python
  // sweeps' _idle_keys.py rules say the same)
  if (!m.floating_base) {
    for (const char* key : {"base.mass", "base.inertia"}) {
      g.idleIfSet(key, "structure.base is fixed: the base never moves, this value does not act");
    }
    g.idleIfSet("geometry.joint1_position", "structure.base is fixed: joint 1's place on it only shifts the whole "
                                            "gimbal, no figure changes");
    g.idleIfSet("sim.momentum_tol", "structure.base is fixed: no momentum drift is checked, this value does not act");
  }
  const IntegratorParams& p = m.integrator;
  scene_keys::validateBearings(s, g);
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
  const double end = std::max(s.run.duration, 1.0), finest = 8.0 * (std::nextafter(end, HUGE_VAL) - end);
  if (s.model.hasClearance() && p.event_tol < p.substep && n_steps <= RunBounds::kMaxSteps &&
      !(p.event_tol >= finest)) {
    // 8 spacings of doubles at the run's end: below that, bisecting a switch's time stops shrinking its
    // bracket, and the run stopped blaming sim.max_event_iters, which no value of it could help.
    g.refuse("sim.event_tol", "must be at least " + formatNumber(finest) + " s: time is resolved no finer at " +
                                  formatNumber(end) + " s (sim.duration), so no contact switch could be located "
                                  "closer; raise it or shorten the run");
  }
  if (!(p.step / p.substep <= RunBounds::kMaxSubstepsPerStep)) {
    g.refuse("sim.substep", "gives " + formatNumber(p.step / p.substep) + " sub-steps per step, more than " +
                                formatNumber(RunBounds::kMaxSubstepsPerStep));
  }
  if (p.max_event_iters > RunBounds::kMaxEventIters) {
    g.refuse("sim.max_event_iters", "must be <= " + std::to_string(RunBounds::kMaxEventIters));
  }
}



}  // namespace

const KeyTable<Scene>& sceneTable() {
  static const KeyTable<Scene> table{
      {"a scene", "scene file", "`gimbalsim keys`", ""}, keys(), validate, scene_keys::deriveBearings, scene_keys::aliases()};
  return table;
}

std::vector<KeyInfo> sceneKeys() { return sceneTable().info(); }

namespace {

/// A model whose first row the arithmetic cannot hold is refused, not run (pass 39: shaft2.mass 1e9 kg with
/// shaft2.com 1000 m, each in its range, gave a mass matrix no double solves: NaN accelerations at t = 0, a run
/// "stopped" with no good row). Every key passed its own range; their product is judged here.
void refuseUnsolvableStart(const Scene& sc, const std::string& origin) {
  Simulator at_start(sc);
  if (rowFinite(at_start.output())) return;
  // A refusal names a key (a sweep's status is refused:<key>; pass 40 found "refused:" bare): the body carrying
  // the most inertia about its frame, m |com|^2 + trace(I), names its mass, the usual cause of the span.
  const Model& m = sc.model;
  const std::pair<const char*, const BodyParams*> bodies[] = {
      {"base.mass", &m.base}, {"shaft1.mass", &m.shaft1}, {"shaft2.mass", &m.shaft2}};
  const char* key = bodies[0].first;
  double most = -1.0;
  for (const auto& [name, b] : bodies) {
    const double carried = b->mass * b->com.squaredNorm() + b->inertia.trace();  // [kg m^2]
    if (carried > most) most = carried, key = name;
  }
  const std::string why = "the model's first row is not finite (NaN or Inf accelerations at its initial state): its "
                          "bodies' mass properties (base.*, shaft1.*, shaft2.*: mass, com, inertia) span further than "
                          "double precision solves";
  throw SceneError(std::vector<Problem>{{origin + ": key '" + key + "': " + why, key, origin, 0, 0, 0}});
}

}  // namespace

void finishScene(Scene& sc, const std::string& origin, std::vector<std::string> warnings) {
  sc.warnings = std::move(warnings);
  sc.model.finalize();
  if (sc.model.name.empty()) sc.model.name = origin;
  refuseUnsolvableStart(sc, origin);
}

std::string readSceneFile(const std::string& path) {
  std::string text;
  std::string why;
  if (!readFile(path, text, &why)) throw SceneError(path + ": cannot open scene file: " + why);
  return text;
}

Scene loadSceneText(const std::string& yaml, const std::string& origin, const std::vector<std::string>& overrides,
                    std::size_t printed) {
  std::vector<std::string> warnings;
  std::vector<std::pair<int, std::string>> idle_sets;
  Scene out = loadKeys<SceneError>(sceneTable(), yaml, origin, overrides, &warnings, printed, &idle_sets);
  out.idle_sets = std::move(idle_sets);
  finishScene(out, origin, std::move(warnings));
  return out;
}

Scene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
  return loadSceneText(readSceneFile(path), path, overrides);
}

std::string sharedClearanceProblem(const Model& m, double c) {
  if (!m.hasClearance()) return "both joints are ideal: no bearing has a clearance to set";
  const ClearanceKind kinds[2] = {m.joint1_kind, m.joint2_kind};
  for (int j = 0; j < 2; ++j) {
    // c derived as R_i - R_j (setClearance): equal to the value set within rounding.
    if (kinds[j] != ClearanceKind::Ideal && std::abs(m.bearing[j].clearance - c) <= 1e-9 * std::abs(c)) return "";
  }
  return "each bearing keeps its own jointN.contact.clearance, so contact.clearance acts on none";
}

std::string idealSceneProblem(const Model& m) {
  std::string why;
  const ClearanceKind kinds[2] = {m.joint1_kind, m.joint2_kind};
  for (int j = 0; j < 2; ++j) {
    if (kinds[j] == ClearanceKind::Ideal) continue;
    why += std::string(why.empty() ? "" : " and ") + "structure.joint" + std::to_string(j + 1) + " is " +
           kindName(kinds[j]);
  }
  return why.empty() ? "" : why + ": the ideal run needs both joints ideal (a scene like tools/scenes/paper_ideal.yaml)";
}

}  // namespace gimbalsim
