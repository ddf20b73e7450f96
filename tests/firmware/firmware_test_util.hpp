// Helpers of the firmware core tests (firmware_core_test, fault_schedule_test).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "gimbalsim/firmware_sim/firmware.hpp"
#include "test_util.hpp"

namespace gimbalsim::firmware::test_helpers {

/// A torque command with seq, the status it answers and the two torques [N m].
inline Command torqueCommand(std::int64_t seq, std::int64_t status_seq, double tau1, double tau2) {
  Command c;
  c.seq = seq;
  c.status_seq = status_seq;
  c.mode = kModeTorque;
  c.torque[0] = tau1;
  c.torque[1] = tau2;
  return c;
}

/// Fixed-base ideal gimbal: the cheapest plant, for the behaviour tests.
inline PlantScene benchScene(std::vector<std::string> sets = {}) {
  sets.insert(sets.begin(), "structure.base=fixed");
  return test::plant("paper_ideal", sets);
}
using Bench = FixedIdeal;

}  // namespace gimbalsim::firmware::test_helpers
