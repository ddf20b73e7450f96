// Checking a checkpoint that comes from outside (a pickle, a setter, arrays
// given by a user) before the step sees it: a State is validated like a scene,
// every field finite and in range, each refusal naming the field.
#pragma once

#include <string>
#include <vector>

#include "gimbalsim/dynamics/model.hpp"
#include "gimbalsim/dynamics/simulator.hpp"

namespace gimbalsim {

/// Largest step index a restored time may sit at: t / sim.step <= 2^50, so the
/// step counter k (long long) and k + 2^40 (the most one call steps) never
/// overflow, and t = k sim.step stays exact in a double.
inline constexpr long long kMaxRestoredStepIndex = 1LL << 50;

/// The problems of `s`, each "State.<field> ...: why". Without a model, what
/// holds for any scene (a known variant, sizes, finite values, ranges); with
/// one, also what its scene implies (the same variant, t reachable with its
/// sim.step, |ecc| inside the bearing, h_next within its sub-steps). Empty: good.
std::vector<std::string> savedStateProblems(const SavedState& s, const Model* m = nullptr);

/// The same, thrown as std::invalid_argument (every problem, one per line).
void checkSavedState(const SavedState& s, const Model* m = nullptr);

}  // namespace gimbalsim
