#include "gimbalsim/dynamics/scene.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace gimbalsim {

SceneError::SceneError(std::vector<std::string> problems)
    : std::runtime_error([&] {
        std::string all;
        for (const auto& p : problems) all += (all.empty() ? "" : "\n") + p;
        return all;
      }()),
      problems_(std::move(problems)) {}

namespace {

/// A value given for a key, and where it was given.
struct Given {
  YAML::Node node;
  std::string where;  // "file:line:col" or "--set #k"
};

struct ConvertError {
  std::string msg;
};

double asNumber(const YAML::Node& n) {
  if (!n.IsScalar()) throw ConvertError{"expected a number"};
  double x;
  if (!YAML::convert<double>::decode(n, x)) throw ConvertError{"expected a number, got '" + n.Scalar() + "'"};
  if (!std::isfinite(x)) throw ConvertError{"must be finite, got '" + n.Scalar() + "'"};
  return x;
}

int asInt(const YAML::Node& n) {
  const double x = asNumber(n);
  if (x != std::floor(x) || std::fabs(x) > 1e9) throw ConvertError{"expected a whole number"};
  return static_cast<int>(x);
}

template <int N>
Eigen::Matrix<double, N, 1> asVector(const YAML::Node& n) {
  if (!n.IsSequence() || static_cast<int>(n.size()) != N) {
    throw ConvertError{"expected a list of " + std::to_string(N) + " numbers"};
  }
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v(i) = asNumber(n[i]);
  return v;
}

/// [Ixx, Iyy, Izz], [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] or a 3x3 list of lists.
Mat3 asInertia(const YAML::Node& n) {
  Mat3 I = Mat3::Zero();
  if (n.IsSequence() && n.size() == 3 && n[0].IsSequence()) {
    for (int r = 0; r < 3; ++r) {
      if (!n[r].IsSequence() || n[r].size() != 3) throw ConvertError{"expected a 3x3 matrix"};
      for (int c = 0; c < 3; ++c) I(r, c) = asNumber(n[r][c]);
    }
    return I;
  }
  if (n.IsSequence() && n.size() == 3) {
    I.diagonal() = asVector<3>(n);
    return I;
  }
  if (n.IsSequence() && n.size() == 6) {
    const auto v = asVector<6>(n);
    I << v(0), v(3), v(4), v(3), v(1), v(5), v(4), v(5), v(2);
    return I;
  }
  throw ConvertError{"expected [Ixx, Iyy, Izz], [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] or a 3x3 matrix"};
}

std::string asString(const YAML::Node& n) {
  if (!n.IsScalar()) throw ConvertError{"expected a string"};
  return n.Scalar();
}

template <class E>
E asEnum(const YAML::Node& n, const std::vector<std::pair<const char*, E>>& names) {
  const std::string s = n.IsScalar() ? n.Scalar() : std::string();
  std::string allowed;
  for (const auto& [name, value] : names) {
    if (s == name) return value;
    allowed += (allowed.empty() ? "" : " | ") + std::string(name);
  }
  throw ConvertError{"expected one of " + allowed + (s.empty() ? "" : ", got '" + s + "'")};
}

struct Spec {
  const char* key;
  const char* type;
  const char* unit;
  const char* help;
  std::function<void(Model&, const YAML::Node&)> apply;
};

const std::vector<Spec>& specs() {
  using N = const YAML::Node&;
  static const std::vector<Spec> s = {
      {"name", "string", "", "scene name", [](Model& m, N n) { m.name = asString(n); }},
      {"structure.base", "floating|fixed", "", "free-floating base or gimbal on a ground bench",
       [](Model& m, N n) {
         m.floating_base = asEnum<bool>(n, {{"floating", true}, {"fixed", false}});
       }},
      {"structure.joint2", "ideal|clearance", "", "elevation joint model",
       [](Model& m, N n) { m.clearance = asEnum<bool>(n, {{"ideal", false}, {"clearance", true}}); }},
      {"base.mass", "number", "kg", "base (satellite) mass", [](Model& m, N n) { m.base.mass = asNumber(n); }},
      {"base.inertia", "inertia", "kg m^2", "about the base CoM, base frame",
       [](Model& m, N n) { m.base.inertia = asInertia(n); }},
      {"shaft1.mass", "number", "kg", "shaft 1 mass", [](Model& m, N n) { m.shaft1.mass = asNumber(n); }},
      {"shaft1.com", "vec3", "m", "shaft 1 CoM from joint 1, shaft 1 frame",
       [](Model& m, N n) { m.shaft1.com = asVector<3>(n); }},
      {"shaft1.inertia", "inertia", "kg m^2", "about shaft 1's CoM, shaft 1 frame",
       [](Model& m, N n) { m.shaft1.inertia = asInertia(n); }},
      {"shaft2.mass", "number", "kg", "shaft 2 + antenna mass", [](Model& m, N n) { m.shaft2.mass = asNumber(n); }},
      {"shaft2.com", "vec3", "m", "shaft 2 CoM from joint 2 (journal centre), shaft 2 frame",
       [](Model& m, N n) { m.shaft2.com = asVector<3>(n); }},
      {"shaft2.inertia", "inertia", "kg m^2", "about shaft 2's CoM, shaft 2 frame",
       [](Model& m, N n) { m.shaft2.inertia = asInertia(n); }},
      {"geometry.joint1_position", "vec3", "m", "joint 1 from the base CoM, base frame",
       [](Model& m, N n) { m.r_J1_B_B = asVector<3>(n); }},
      {"geometry.joint1_axis", "vec3", "-", "joint 1 (azimuth) axis, base frame",
       [](Model& m, N n) { m.k1_B = asVector<3>(n); }},
      {"geometry.joint2_position", "vec3", "m", "joint 2 (bearing centre) from joint 1, shaft 1 frame",
       [](Model& m, N n) { m.r_J2_S1_S1 = asVector<3>(n); }},
      {"geometry.joint2_axis", "vec3", "-", "joint 2 (elevation) axis, shaft 1 frame",
       [](Model& m, N n) { m.k2_S1 = asVector<3>(n); }},
      {"geometry.boresight", "vec3", "-", "antenna boresight, shaft 2 frame",
       [](Model& m, N n) { m.boresight_S2 = asVector<3>(n); }},
      {"contact.bearing_radius", "number", "m", "R_i, bearing (on shaft 1)",
       [](Model& m, N n) { m.contact.bearing_radius = asNumber(n); }},
      {"contact.journal_radius", "number", "m", "R_j, journal (on shaft 2); or give contact.clearance",
       [](Model& m, N n) { m.contact.journal_radius = asNumber(n); }},
      {"contact.clearance", "number", "m", "radial clearance c; sets journal_radius = bearing_radius - c",
       [](Model& m, N n) { m.contact.journal_radius = m.contact.bearing_radius - asNumber(n); }},
      {"contact.radius_mode", "paper|conformal", "", "R in the Hertz stiffness",
       [](Model& m, N n) {
         m.contact.radius_mode =
             asEnum<RadiusMode>(n, {{"paper", RadiusMode::Paper}, {"conformal", RadiusMode::Conformal}});
       }},
      {"contact.E_bearing", "number", "Pa", "Young's modulus, bearing",
       [](Model& m, N n) { m.contact.E_bearing = asNumber(n); }},
      {"contact.nu_bearing", "number", "-", "Poisson's ratio, bearing",
       [](Model& m, N n) { m.contact.nu_bearing = asNumber(n); }},
      {"contact.E_journal", "number", "Pa", "Young's modulus, journal",
       [](Model& m, N n) { m.contact.E_journal = asNumber(n); }},
      {"contact.nu_journal", "number", "-", "Poisson's ratio, journal",
       [](Model& m, N n) { m.contact.nu_journal = asNumber(n); }},
      {"contact.exponent", "number", "-", "Hertz exponent n",
       [](Model& m, N n) { m.contact.exponent = asNumber(n); }},
      {"contact.stiffness_scale", "number", "-", "multiplies the Hertz stiffness K",
       [](Model& m, N n) { m.contact.stiffness_scale = asNumber(n); }},
      {"contact.damping", "none|hunt_crossley|lankarani_nikravesh|flores", "", "hysteresis damping law",
       [](Model& m, N n) {
         m.contact.damping = asEnum<DampingLaw>(n, {{"none", DampingLaw::None},
                                                    {"hunt_crossley", DampingLaw::HuntCrossley},
                                                    {"lankarani_nikravesh", DampingLaw::LankaraniNikravesh},
                                                    {"flores", DampingLaw::Flores}});
       }},
      {"contact.restitution", "number", "-", "coefficient of restitution c_e, in (0, 1]",
       [](Model& m, N n) { m.contact.restitution = asNumber(n); }},
      {"contact.v0_min", "number", "m/s", "floor on the impact velocity v0 in the damping",
       [](Model& m, N n) { m.contact.v0_min = asNumber(n); }},
      {"friction.law", "none|coulomb|ambrosio|coulomb_stick", "",
       "tangential force law (coulomb_stick: set-valued Coulomb, stick and slip located as events)",
       [](Model& m, N n) {
         m.contact.friction = asEnum<FrictionLaw>(
             n, {{"none", FrictionLaw::None}, {"coulomb", FrictionLaw::Coulomb}, {"ambrosio", FrictionLaw::Ambrosio},
                 {"coulomb_stick", FrictionLaw::CoulombStick}});
       }},
      {"friction.mu", "number", "-", "dynamic friction coefficient", [](Model& m, N n) { m.contact.mu = asNumber(n); }},
      {"friction.v_a", "number", "m/s", "Ambrosio: no friction below this |v_t|",
       [](Model& m, N n) { m.contact.v_a = asNumber(n); }},
      {"friction.v_b", "number", "m/s", "Ambrosio: full friction above this |v_t|",
       [](Model& m, N n) { m.contact.v_b = asNumber(n); }},
      {"torque.tau1", "number", "N m", "constant joint 1 (azimuth) torque", [](Model& m, N n) { m.torque(0) = asNumber(n); }},
      {"torque.tau2", "number", "N m", "constant joint 2 (elevation) torque", [](Model& m, N n) { m.torque(1) = asNumber(n); }},
      {"torque.limit", "vec2", "N m", "motor torque limit per axis", [](Model& m, N n) { m.torque_limit = asVector<2>(n); }},
      {"initial.theta1", "number", "rad", "initial joint 1 angle", [](Model& m, N n) { m.initial.theta1 = asNumber(n); }},
      {"initial.theta2", "number", "rad", "initial joint 2 angle", [](Model& m, N n) { m.initial.theta2 = asNumber(n); }},
      {"initial.dtheta1", "number", "rad/s", "initial joint 1 rate", [](Model& m, N n) { m.initial.dtheta1 = asNumber(n); }},
      {"initial.dtheta2", "number", "rad/s", "initial joint 2 rate", [](Model& m, N n) { m.initial.dtheta2 = asNumber(n); }},
      {"initial.ecc", "vec2", "m", "initial journal eccentricity in the joint-2 plane (u1, u2)",
       [](Model& m, N n) { m.initial.ecc = asVector<2>(n); }},
      {"sim.duration", "number", "s", "simulated time", [](Model& m, N n) { m.duration = asNumber(n); }},
      {"sim.step", "number", "s", "RK4 step h", [](Model& m, N n) { m.integrator.step = asNumber(n); }},
      {"sim.output_interval", "number", "s", "CSV row spacing, a multiple of sim.step",
       [](Model& m, N n) { m.output_interval = asNumber(n); }},
      {"sim.substep", "number", "s", "RK4 sub-step near and in contact, <= sim.step",
       [](Model& m, N n) { m.integrator.substep = asNumber(n); }},
      {"sim.event_tol", "number", "s", "contact switch location tolerance",
       [](Model& m, N n) { m.integrator.event_tol = asNumber(n); }},
      {"sim.max_substeps", "int", "-", "sub-step cap per step (0 = 2 step/substep + 4 max_event_iters + 4; adaptive: step/substep at least 500)",
       [](Model& m, N n) { m.integrator.max_substeps = asInt(n); }},
      {"sim.substep_policy", "fixed|adaptive", "",
       "contact sub-steps: fixed sim.substep, or adaptive local error control to sim.substep_tol",
       [](Model& m, N n) {
         m.integrator.substep_policy =
             asEnum<SubstepPolicy>(n, {{"fixed", SubstepPolicy::Fixed}, {"adaptive", SubstepPolicy::Adaptive}});
       }},
      {"sim.substep_tol", "number", "-", "adaptive: local error per sub-step, max_i |err_i| / (1 + |y_i|)",
       [](Model& m, N n) { m.integrator.substep_tol = asNumber(n); }},
      {"sim.substep_min", "number", "s", "adaptive: smallest sub-step (taken even above tolerance, counted)",
       [](Model& m, N n) { m.integrator.substep_min = asNumber(n); }},
      {"sim.substep_max", "number", "s", "adaptive: largest sub-step near contact (0 = sim.step)",
       [](Model& m, N n) { m.integrator.substep_max = asNumber(n); }},
      {"sim.max_event_iters", "int", "-", "switch location iteration cap",
       [](Model& m, N n) { m.integrator.max_event_iters = asInt(n); }},
      {"sim.velocity_limit", "number", "rad/s, m/s", "any |v_i| above this stops the run as diverging",
       [](Model& m, N n) { m.integrator.velocity_limit = asNumber(n); }},
      {"sim.penetration_limit", "number", "m", "penetration above this stops the run (0 = the clearance)",
       [](Model& m, N n) { m.integrator.penetration_limit = asNumber(n); }},
      {"sim.momentum_tol", "number", "-",
       "relative momentum drift (floating base) that stops the run, checked at output rows (0 = off)",
       [](Model& m, N n) { m.integrator.momentum_tol = asNumber(n); }},
      {"sim.energy_tol", "number", "-",
       "relative rise of kinetic + Hertz - torque work that stops the run, checked at output rows (0 = off)",
       [](Model& m, N n) { m.integrator.energy_tol = asNumber(n); }},
      {"sim.min_substeps_per_impact", "number", "-",
       "fixed policy: an impact lasting fewer sub-steps than this (Hertz estimate) stops the run (0 = off)",
       [](Model& m, N n) { m.integrator.min_substeps_per_impact = asNumber(n); }},
      {"sensors.encoder_resolution", "number", "rad", "firmware_sim: encoder quantum (0 = unquantized)",
       [](Model& m, N n) { m.sensors.encoder_resolution = asNumber(n); }},
      {"sensors.encoder_noise", "number", "rad", "firmware_sim: Gaussian encoder noise sigma (0 = none)",
       [](Model& m, N n) { m.sensors.encoder_noise = asNumber(n); }},
      {"sensors.rate_noise", "number", "rad/s", "firmware_sim: Gaussian rate noise sigma (0 = none)",
       [](Model& m, N n) { m.sensors.rate_noise = asNumber(n); }},
      {"sensors.seed", "int", "-", "firmware_sim: sensor noise seed (>= 0)",
       [](Model& m, N n) { m.sensors.seed = asInt(n); }},
  };
  return s;
}

std::string markOf(const std::string& origin, const YAML::Node& n) {
  const YAML::Mark mk = n.Mark();
  if (mk.line < 0) return origin;
  return origin + ":" + std::to_string(mk.line + 1) + ":" + std::to_string(mk.column + 1);
}

void flatten(const YAML::Node& n, const std::string& prefix, const std::string& origin,
             std::map<std::string, Given>& out, std::vector<std::string>& problems) {
  for (auto it = n.begin(); it != n.end(); ++it) {
    const std::string k = it->first.as<std::string>();
    const std::string full = prefix.empty() ? k : prefix + "." + k;
    const YAML::Node& v = it->second;
    const bool is_section = v.IsMap();
    if (is_section) {
      flatten(v, full, origin, out, problems);
    } else {
      out[full] = Given{v, markOf(origin, it->first)};
    }
  }
}

bool known(const std::string& key) {
  for (const auto& s : specs()) {
    if (key == s.key) return true;
  }
  return false;
}

bool isSpd(const Mat3& I) {
  if (!I.isApprox(I.transpose(), 1e-12)) return false;
  Eigen::SelfAdjointEigenSolver<Mat3> es(I);
  return es.eigenvalues().minCoeff() > 0.0;
}

}  // namespace

std::vector<KeyInfo> sceneKeys() {
  std::vector<KeyInfo> out;
  for (const auto& s : specs()) out.push_back({s.key, s.type, s.unit, s.help});
  return out;
}

LoadedScene loadSceneText(const std::string& yaml, const std::string& origin,
                          const std::vector<std::string>& overrides) {
  std::vector<std::string> problems;
  std::map<std::string, Given> given;
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw SceneError({origin + ":" + std::to_string(e.mark.line + 1) + ":" +
                      std::to_string(e.mark.column + 1) + ": not valid YAML: " + e.msg});
  }
  if (root.IsDefined() && !root.IsNull()) {
    if (!root.IsMap()) throw SceneError({origin + ": a scene must be a mapping of sections"});
    flatten(root, "", origin, given, problems);
  }
  for (const auto& [k, g] : given) {
    if (!known(k)) problems.push_back(g.where + ": unknown key '" + k + "' (see `gimbalsim keys`)");
  }
  int idx = 0;
  for (const std::string& o : overrides) {
    ++idx;
    const std::string where = "--set #" + std::to_string(idx) + " '" + o + "'";
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0) {
      problems.push_back(where + ": expected key=value");
      continue;
    }
    const std::string key = o.substr(0, eq), val = o.substr(eq + 1);
    if (!known(key)) {
      problems.push_back(where + ": unknown key '" + key + "' (see `gimbalsim keys`)");
      continue;
    }
    try {
      // A later --set of either radius form wins over the other.
      if (key == "contact.clearance") given.erase("contact.journal_radius");
      if (key == "contact.journal_radius") given.erase("contact.clearance");
      given[key] = Given{YAML::Load(val), where};
    } catch (const YAML::Exception& e) {
      problems.push_back(where + ": value is not valid: " + e.msg);
    }
  }
  if (given.count("contact.clearance") && given.count("contact.journal_radius")) {
    problems.push_back(given["contact.clearance"].where +
                       ": give either contact.clearance or contact.journal_radius, not both");
  }

  LoadedScene out;
  Model& m = out.model;
  // Apply in registry order (contact.clearance after the radii it depends on).
  for (const auto& s : specs()) {
    auto it = given.find(s.key);
    if (it == given.end()) continue;
    try {
      s.apply(m, it->second.node);
    } catch (const ConvertError& e) {
      problems.push_back(it->second.where + ": key '" + s.key + "': " + e.msg);
    } catch (const YAML::Exception& e) {
      problems.push_back(it->second.where + ": key '" + s.key + "': " + e.msg);
    }
  }
  if (!problems.empty()) throw SceneError(problems);

  // ---- physical validation ----
  auto at = [&](const char* key) {
    auto it = given.find(key);
    return it == given.end() ? origin + ": (default of " + key + ")" : it->second.where;
  };
  auto refuse = [&](const char* key, const std::string& msg) {
    problems.push_back(at(key) + ": key '" + key + "': " + msg);
  };
  auto num = [](double x) {
    std::ostringstream os;
    os << x;
    return os.str();
  };
  const std::pair<const char*, const BodyParams*> bodies[] = {
      {"base", &m.base}, {"shaft1", &m.shaft1}, {"shaft2", &m.shaft2}};
  for (const auto& [name, b] : bodies) {
    const std::string mk = std::string(name) + ".mass", ik = std::string(name) + ".inertia";
    if (!(b->mass > 0.0)) refuse(mk.c_str(), "mass must be > 0, got " + num(b->mass));
    if (!isSpd(b->inertia)) {
      refuse(ik.c_str(), "inertia must be symmetric positive definite");
    } else {
      const Eigen::Vector3d p = Eigen::SelfAdjointEigenSolver<Mat3>(b->inertia).eigenvalues();
      for (int i = 0; i < 3; ++i) {
        if (p(i) > p((i + 1) % 3) + p((i + 2) % 3) * (1.0 + 1e-12)) {
          out.warnings.push_back(at(ik.c_str()) + ": key '" + ik +
                                 "': principal moments break the triangle inequality (no real rigid "
                                 "body has them); the equations stay well defined, continuing");
          break;
        }
      }
    }
  }
  if (m.k1_B.norm() < 1e-12) refuse("geometry.joint1_axis", "axis must be non-zero");
  if (m.k2_S1.norm() < 1e-12) refuse("geometry.joint2_axis", "axis must be non-zero");
  if (m.boresight_S2.norm() < 1e-12) refuse("geometry.boresight", "boresight must be non-zero");
  const ContactParams& c = m.contact;
  const char* jr = given.count("contact.clearance") ? "contact.clearance" : "contact.journal_radius";
  if (!(c.bearing_radius > 0.0)) refuse("contact.bearing_radius", "must be > 0, got " + num(c.bearing_radius));
  if (!(c.journal_radius > 0.0)) refuse(jr, "journal radius must be > 0, got " + num(c.journal_radius));
  if (given.count("contact.clearance") && !(c.bearing_radius - c.journal_radius >= 0.0)) {
    refuse("contact.clearance", "clearance must not be negative");
  } else if (!(c.journal_radius < c.bearing_radius)) {
    refuse(jr, "journal radius (" + num(c.journal_radius) + " m) must be < bearing radius (" +
                   num(c.bearing_radius) + " m)");
  }
  if (!(c.E_bearing > 0.0)) refuse("contact.E_bearing", "must be > 0");
  if (!(c.E_journal > 0.0)) refuse("contact.E_journal", "must be > 0");
  if (!(c.nu_bearing >= 0.0 && c.nu_bearing < 0.5)) refuse("contact.nu_bearing", "must be in [0, 0.5)");
  if (!(c.nu_journal >= 0.0 && c.nu_journal < 0.5)) refuse("contact.nu_journal", "must be in [0, 0.5)");
  if (!(c.exponent >= 1.0 && c.exponent <= 3.0)) refuse("contact.exponent", "must be in [1, 3]");
  if (!(c.stiffness_scale > 0.0)) refuse("contact.stiffness_scale", "must be > 0");
  if (!(c.restitution > 0.0 && c.restitution <= 1.0)) {
    refuse("contact.restitution", "must be in (0, 1], got " + num(c.restitution));
  }
  if (!(c.v0_min > 0.0)) refuse("contact.v0_min", "must be > 0");
  if (!(c.mu >= 0.0)) refuse("friction.mu", "must be >= 0");
  if (!(c.v_a >= 0.0)) refuse("friction.v_a", "must be >= 0");
  if (!(c.v_b > c.v_a)) refuse("friction.v_b", "must be > friction.v_a");
  if (!(m.torque_limit.minCoeff() > 0.0)) refuse("torque.limit", "must be > 0");
  const IntegratorParams& p = m.integrator;
  if (!(m.duration > 0.0)) refuse("sim.duration", "must be > 0");
  if (!(p.step > 0.0)) refuse("sim.step", "must be > 0");
  if (!(p.substep > 0.0 && p.substep <= p.step)) refuse("sim.substep", "must be in (0, sim.step]");
  if (!(p.event_tol > 0.0 && p.event_tol < p.substep)) refuse("sim.event_tol", "must be in (0, sim.substep)");
  if (p.max_substeps < 0) refuse("sim.max_substeps", "must be >= 0");
  if (!(p.substep_tol > 0.0 && p.substep_tol < 1.0)) refuse("sim.substep_tol", "must be in (0, 1)");
  if (!(p.substep_min > 0.0 && p.substep_min <= p.step)) refuse("sim.substep_min", "must be in (0, sim.step]");
  if (!(p.substep_max >= 0.0 && p.substep_max <= p.step)) refuse("sim.substep_max", "must be in [0, sim.step]");
  if (p.max_event_iters < 1) refuse("sim.max_event_iters", "must be >= 1");
  if (!(p.velocity_limit > 0.0)) refuse("sim.velocity_limit", "must be > 0");
  if (!(p.penetration_limit >= 0.0)) refuse("sim.penetration_limit", "must be >= 0");
  if (!(p.min_substeps_per_impact >= 0.0)) refuse("sim.min_substeps_per_impact", "must be >= 0");
  if (!(p.momentum_tol >= 0.0)) refuse("sim.momentum_tol", "must be >= 0");
  if (!(p.energy_tol >= 0.0)) refuse("sim.energy_tol", "must be >= 0");
  if (p.step > 0.0 && m.output_interval > 0.0) {
    const double r = m.output_interval / p.step;
    if (std::fabs(r - std::round(r)) > 1e-6 * r || std::round(r) < 1.0) {
      refuse("sim.output_interval", "must be a whole multiple of sim.step (" + num(p.step) + " s)");
    }
  } else {
    refuse("sim.output_interval", "must be > 0");
  }
  if (!(m.sensors.encoder_resolution >= 0.0)) refuse("sensors.encoder_resolution", "must be >= 0");
  if (!(m.sensors.encoder_noise >= 0.0)) refuse("sensors.encoder_noise", "must be >= 0");
  if (!(m.sensors.rate_noise >= 0.0)) refuse("sensors.rate_noise", "must be >= 0");
  if (m.sensors.seed < 0) refuse("sensors.seed", "must be >= 0");
  if (m.clearance && m.initial.ecc.norm() > c.bearing_radius - c.journal_radius) {
    refuse("initial.ecc", "initial eccentricity exceeds the radial clearance");
  }
  if (!problems.empty()) throw SceneError(problems);
  m.finalize();
  if (m.name.empty()) m.name = origin;
  return out;
}

LoadedScene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw SceneError({path + ": cannot open scene file"});
  std::stringstream ss;
  ss << in.rdbuf();
  return loadSceneText(ss.str(), path, overrides);
}

}  // namespace gimbalsim
