// Shared helpers of the test suite.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/observables.hpp"
#include "gimbalsim/dynamics/scene.hpp"

namespace gimbalsim::test {

inline std::string scenePath(const std::string& name) {
  return std::string(GIMBALSIM_SCENES_DIR) + "/" + name + ".yaml";
}

inline Model scene(const std::string& name, const std::vector<std::string>& sets = {}) {
  return loadScene(scenePath(name), sets).model;
}

inline Input sceneInput(const Model& m) {
  Input u;
  u.tau = m.torque;
  return u;
}

/// Steps s for n steps of the model's h; fails the test on a bad status.
template <class V>
void advance(const Model& m, Data<V>& d, State<V>& s, long long n) {
  const Input u = sceneInput(m);
  for (long long k = 0; k < n; ++k) {
    const StepStatus st = step(m, d, s, u);
    ASSERT_EQ(st, StepStatus::Ok) << describe(st) << " at t = " << d.fail_time;
  }
}

/// Runs a fresh state of variant V to time T and returns it.
template <class V>
State<V> runTo(const Model& m, double T) {
  Data<V> d(m);
  State<V> s = initialState<V>(m);
  advance(m, d, s, std::llround(T / m.integrator.step));
  return s;
}

/// Boresight of a state (inertial frame).
template <class V>
Vec3 boresightOf(const Model& m, const State<V>& s) {
  Data<V> d(m);
  kinematics(m, d, s.q, s.v);
  return boresight(m, d, s);
}

inline double angleBetween(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace gimbalsim::test
