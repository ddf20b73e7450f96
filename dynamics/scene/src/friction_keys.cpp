// The friction keys a bearing's law does not read (docs/scene_keys.md "The two
// bearings"): a --set of one is said to act on nothing, as a bearing key on an
// ideal joint is; the studies refuse it (Scene::idle_sets).
#include "bearing_keys.hpp"

namespace gimbalsim::scene_keys {

namespace {

/// Why a bearing does not read its friction key `suffix` (law, mu, v_a, v_b), or "".
std::string notRead(const ContactParams& b, const std::string& suffix) {
  if (suffix == "law") return b.mu > 0.0 ? "" : "its friction.mu is 0: no friction law acts";
  if (b.friction == FrictionLaw::None) return "its friction.law is none";
  if ((suffix == "v_a" || suffix == "v_b") && b.friction != FrictionLaw::Ambrosio) {
    return "its friction.law is not ambrosio, the one law that reads friction.v_a and friction.v_b";
  }
  if ((suffix == "v_a" || suffix == "v_b") && !(b.mu > 0.0)) return "its friction.mu is 0";
  return "";
}

}  // namespace

// (pass 88) friction.mu under friction.law none, and v_a, v_b under coulomb, ran recorded as applied.
void idleFrictionKeys(const Scene& s, Given& g) {
  const Model& m = s.model;
  for (const char* suffix : {"law", "mu", "v_a", "v_b"}) {
    std::string shared_why;    // why the joints that take the shared key do not read it
    bool shared_read = false;  // a joint with a bearing takes the shared key and reads it
    bool shared_taken = false;
    for (int j = 0; j < 2; ++j) {
      if (m.jointKind(j) == ClearanceKind::Ideal) continue;  // its keys are said not used (validateBearings)
      const std::string joint = "joint " + std::to_string(j + 1);
      const std::string own = "joint" + std::to_string(j + 1) + ".friction." + suffix;
      const std::string why = notRead(m.bearing[j], suffix);
      if (g.has(own)) {
        if (!why.empty()) {
          g.idleIfSet(own, joint + "'s bearing does not read it (" + why + "): this value does not act");
        }
        continue;
      }
      shared_taken = true;
      shared_read = shared_read || why.empty();
      if (!why.empty()) shared_why += (shared_why.empty() ? "" : "; ") + joint + ": " + why;
    }
    const std::string shared = std::string("friction.") + suffix;
    if (shared_taken && !shared_read && g.has(shared)) {
      g.idleIfSet(shared, "no bearing that takes it reads it (" + shared_why + "): this value does not act");
    }
  }
}

}  // namespace gimbalsim::scene_keys
