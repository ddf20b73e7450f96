// libFuzzer target: a State from outside (what a pickle or a user's arrays
// give Simulator.state) restored into a simulator of each compiled variant,
// then stepped. The bytes are the fields (layout below). What must hold: the
// check with a scene is stricter than without one; a refused state leaves
// the simulator as it was; an accepted one steps with time finite and never
// going back (t = 1e300 used to come out as -9.2e15 after one step).
//
// Layout: [0] scene (mod 6), [1] variant name (mod 8: 0-5 the six names,
// 6-7 the scene's own), [2] q size (mod 16), [3] v size (mod 16),
// [4] contact ends (bits 0-2, mod 5) and their sides (bits 3-6),
// [5] friction_mode (int8), [6] steps (1 + mod 4),
// then float64s: t, v0 (every end's), vt_floor, h_next, tau1, tau2, q..., v...
// (missing: 0).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_check.hpp"
#include "gimbalsim/dynamics/saved_state.hpp"
#include "gimbalsim/dynamics/simulator.hpp"
#include "gimbalsim/dynamics/variant.hpp"
#include "gimbalsim/scene/scene.hpp"

namespace {

using gimbalsim::SavedState;

const std::vector<gimbalsim::Scene>& scenes() {
  static const std::vector<gimbalsim::Scene> all = [] {
    std::vector<gimbalsim::Scene> s;
    for (const char* base : {"fixed", "floating"}) {
      for (const char* joint : {"ideal", "clearance", "friction"}) {
        const bool friction = std::strcmp(joint, "friction") == 0;
        s.push_back(gimbalsim::loadSceneText(
            "", "fuzz.yaml",
            {std::string("structure.base=") + base, std::string("structure.joint2=") + (friction ? "clearance" : joint),
             friction ? "friction.law=coulomb_stick" : "friction.law=none", "friction.mu=0.2"}));
      }
    }
    return s;
  }();
  return all;
}

// Today's names and, as a checkpoint saved before both joints were named alike holds them, the old ones.
const char* const kVariants[] = {"fixed_ideal_ideal",    "fixed_ideal_planar",    "fixed_ideal_planar_friction",
                                 "floating_ideal_ideal", "floating_ideal_planar", "floating_ideal_planar_friction",
                                 "fixed_clearance",      "floating_clearance_friction"};

[[noreturn]] void fail(const char* what, const SavedState& s) {
  std::fprintf(stderr, "fuzz_state_restore: %s (variant %s, t = %.17g)\n", what, s.variant.c_str(), s.t);
  std::abort();
}

struct Reader {
  const std::uint8_t* p;
  std::size_t n, at = 0;
  std::uint8_t byte() { return at < n ? p[at++] : 0; }
  double number() {
    double x = 0.0;
    std::uint8_t b[8] = {};
    for (auto& c : b) c = byte();
    std::memcpy(&x, b, sizeof x);
    return x;
  }
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) { return gimbalsim::fuzz::withBounds(argc, argv); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in{data, size};
  const gimbalsim::Scene& scene = scenes()[in.byte() % 6];
  const std::uint8_t name = in.byte() % 10;
  SavedState s;
  s.variant = name < 8 ? kVariants[name] : gimbalsim::variantName(scene.model);
  const int nq = in.byte() % 16, nv = in.byte() % 16;
  const std::uint8_t ends = in.byte();
  for (int e = 0; e < (ends & 7) % 5; ++e) s.in_contact.push_back((ends >> (3 + e)) & 1);
  s.friction_mode = static_cast<std::int8_t>(in.byte());
  const long long steps = 1 + in.byte() % 4;
  s.t = in.number();
  s.v0.assign(s.in_contact.size(), in.number());
  s.vt_floor = in.number();
  s.h_next = in.number();
  const double tau1 = in.number(), tau2 = in.number();
  for (int i = 0; i < nq; ++i) s.q.push_back(in.number());
  for (int i = 0; i < nv; ++i) s.v.push_back(in.number());

  const bool alone = gimbalsim::savedStateProblems(s).empty();
  const bool with_scene = gimbalsim::savedStateProblems(s, &scene.model).empty();
  if (with_scene && !alone) fail("accepted with a scene but refused without one", s);

  gimbalsim::Simulator sim(scene);
  const SavedState before = sim.save();
  try {
    sim.restore(s);
  } catch (const std::invalid_argument& e) {
    if (with_scene) fail("restore refused what the check accepted", s);
    if (std::string(e.what()).rfind("State.", 0) != 0) fail("a refusal that names no field", s);
    const SavedState after = sim.save();
    if (after.t != before.t || after.q != before.q || after.v != before.v) {
      fail("a refused state changed the simulator", s);
    }
    return 0;
  }
  if (!with_scene) fail("restore accepted what the check refused", s);
  if (!std::isfinite(tau1) || !std::isfinite(tau2)) return 0;  // the bindings refuse these before stepping
  (void)sim.step(gimbalsim::Vec2(tau1, tau2), steps);
  const double t = sim.time();
  if (!std::isfinite(t) || t < s.t) fail("time after stepping is not finite or went back", s);
  (void)sim.output();
  return 0;
}
