#include "mujoco_peer.hpp"

#include <mujoco/mujoco.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include "gimbalsim/input/key_registry.hpp"

namespace gimbalsim::workprec {

namespace {

std::string vec(const Vec3& v) {
  std::ostringstream os;
  os.precision(17);
  os << v.x() << ' ' << v.y() << ' ' << v.z();
  return os.str();
}

/// <inertial> at the CoM: MuJoCo's fullinertia is Ixx Iyy Izz Ixy Ixz Iyz.
std::string inertial(const BodyParams& b) {
  std::ostringstream os;
  os.precision(17);
  const Mat3& I = b.inertia;
  os << "<inertial pos=\"" << vec(b.com) << "\" mass=\"" << b.mass << "\" fullinertia=\"" << I(0, 0) << ' '
     << I(1, 1) << ' ' << I(2, 2) << ' ' << I(0, 1) << ' ' << I(0, 2) << ' ' << I(1, 2) << "\"/>";
  return os.str();
}

struct MjDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
  void operator()(mjData* d) const { mj_deleteData(d); }
};

/// Loads MJCF text (through a file: MuJoCo 2.2's loader reads files or a VFS).
std::unique_ptr<mjModel, MjDeleter> load(const std::string& xml, std::string& error) {
  const auto path = std::filesystem::temp_directory_path() / ("gimbalsim_mujoco_" + std::to_string(::getpid()) + ".xml");
  std::ofstream(path) << xml;
  char err[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof err);
  std::filesystem::remove(path);
  if (!m) error = err;
  return std::unique_ptr<mjModel, MjDeleter>(m);
}

/// Initial state and torques as gimbalsim's initialState() and Input.
void setUp(const RunSpec& m, const mjModel* mm, mjData* d) {
  mj_resetData(mm, d);
  // qpos: base pos (3), quat w x y z (4), theta1, theta2; qvel: base linear
  // (world) 3, angular (body) 3, dtheta1, dtheta2. The base starts at rest.
  d->qpos[7] = m.initial.theta1;
  d->qpos[8] = m.initial.theta2;
  d->qvel[6] = m.initial.dtheta1;
  d->qvel[7] = m.initial.dtheta2;
  d->qfrc_applied[6] = m.torque.x();
  d->qfrc_applied[7] = m.torque.y();
}

}  // namespace

std::string mjcfOf(const Model& m, double timestep) {
  if (!m.floating_base || m.hasClearance()) throw std::invalid_argument("the MuJoCo peer models a floating base with ideal joints");
  if (m.base.com.norm() != 0.0) throw std::invalid_argument("base CoM must be the base frame origin");
  std::ostringstream x;
  x.precision(17);
  x << "<mujoco model=\"" << m.name << "\">\n"
    << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
    << "  <option timestep=\"" << timestep << "\" integrator=\"RK4\" gravity=\"0 0 0\">\n"
    << "    <flag contact=\"disable\" constraint=\"disable\" energy=\"enable\"/>\n"
    << "  </option>\n"
    << "  <worldbody>\n"
    << "    <body name=\"base\" pos=\"0 0 0\">\n"  // body frame = base CoM frame
    << "      <freejoint name=\"base\"/>\n"
    << "      " << inertial(m.base) << "\n"
    << "      <body name=\"shaft1\" pos=\"" << vec(m.r_J1_B_B) << "\">\n"  // frame at joint 1
    << "        <joint name=\"joint1\" type=\"hinge\" pos=\"0 0 0\" axis=\"" << vec(m.k1_B) << "\"/>\n"
    << "        " << inertial(m.shaft1) << "\n"
    << "        <body name=\"shaft2\" pos=\"" << vec(m.r_J2_S1_S1) << "\">\n"  // frame at joint 2
    << "          <joint name=\"joint2\" type=\"hinge\" pos=\"0 0 0\" axis=\"" << vec(m.k2_S1) << "\"/>\n"
    << "          " << inertial(m.shaft2) << "\n"
    << "        </body>\n      </body>\n    </body>\n  </worldbody>\n</mujoco>\n";
  return x.str();
}

std::vector<Point> mujocoPoints(const Scene& sc, const Trajectory& ref, const std::vector<double>& steps,
                                int repeats) {
  std::vector<Point> out;
  for (double h : steps) {
    Point p;
    p.policy = "MuJoCo 2.2 RK4";
    p.h = p.substep = h;
    const double r = sc.run.output_interval / h;
    if (!isWholeMultiple(sc.run.output_interval, h)) continue;
    std::string error;
    auto mm = load(mjcfOf(sc.model, h), error);
    if (!mm) {
      p.note = "MuJoCo refused the model: " + error;
      for (char& c : p.note) c = c == '\n' ? ' ' : c;
      out.push_back(p);
      break;  // same refusal at every step
    }
    std::unique_ptr<mjData, MjDeleter> d(mj_makeData(mm.get()));
    const int shaft2 = mj_name2id(mm.get(), mjOBJ_BODY, "shaft2");
    const long long n = std::llround(sc.run.duration / h), every = std::llround(r);
    // Error run: rows at the output interval.
    Trajectory run;
    setUp(sc.run, mm.get(), d.get());
    mj_forward(mm.get(), d.get());
    auto row = [&] {
      const mjtNum* R = d->xmat + 9 * shaft2;  // row-major world rotation of shaft 2
      const Vec3 b = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R) * sc.model.boresight_S2;
      run.t.push_back(d->time);
      run.theta1.push_back(d->qpos[7]);
      run.theta2.push_back(d->qpos[8]);
      run.bore.push_back(b);
    };
    row();
    for (long long k = 1; k <= n; ++k) {
      mj_step(mm.get(), d.get());
      if (k % every == 0 || k == n) {
        mj_kinematics(mm.get(), d.get());  // xmat at the new qpos
        row();
      }
    }
    run.substeps = n;
    run.momentum_drift_rel = std::numeric_limits<double>::quiet_NaN();
    p.ok = compare(run, ref, p);
    // Timed runs: stepping only.
    std::vector<double> cpu;
    for (int i = 0; i < repeats && p.ok; ++i) {
      setUp(sc.run, mm.get(), d.get());
      const double t0 = threadCpuSeconds();
      for (long long k = 0; k < n; ++k) mj_step(mm.get(), d.get());
      cpu.push_back(threadCpuSeconds() - t0);
    }
    if (p.ok) {
      p.repeats = repeats;
      p.cpu_per_sim_s = median(cpu) / sc.run.duration;
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace gimbalsim::workprec
