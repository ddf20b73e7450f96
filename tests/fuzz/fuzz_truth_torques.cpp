// libFuzzer target: torque_replay's reader of a truth CSV
// (tools/bench/truth_torques.hpp) on arbitrary bytes. It returns torques,
// finite and one pair per row, or throws std::runtime_error naming the input;
// nothing else, never a crash.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

#include "truth_torques.hpp"

namespace {
void check(bool ok, const char* why) {
  if (ok) return;
  std::fprintf(stderr, "fuzz check failed: %s\n", why);
  std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    // a few of the truth's state columns, as torque_replay asks for all of them: each row hashed
    const gimbalsim::bench::Torques t =
        gimbalsim::bench::parseTorques(in, "fuzz.csv", {"theta1_rad", "ecc2_x_m", "delta2_m", "energy_J"});
    check(t.compared_columns.size() <= 4, "a compared column not asked for");
    check(t.row_hash.size() == (t.compared_columns.empty() ? 0 : t.tau1.size()), "not one hash per row");
    check(t.tau1.size() == t.tau2.size() && t.tau1.size() >= 2, "not one torque pair per row, two rows at least");
    for (std::size_t k = 0; k < t.tau1.size(); ++k) {
      check(std::isfinite(t.tau1[k]) && std::isfinite(t.tau2[k]), "a torque that is not finite");
    }
    check(t.t_s.empty() || t.t_s.size() == t.tau1.size(), "not one time per row");
    for (std::size_t k = 1; k < t.t_s.size(); ++k) check(t.t_s[k] > t.t_s[k - 1], "times not in order");
  } catch (const std::runtime_error& e) {
    check(std::string(e.what()).rfind("fuzz.csv", 0) == 0, "a refusal that does not name the input");
  }
  return 0;
}
