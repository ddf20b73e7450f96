// The truth message as published: the plant's truth with the truth
// observer's target line of sight and pointing error filled in. firmware_sim
// (both loops) and the in-process closed loop publish it this way.
#pragma once

#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/pointing/truth_observer.hpp"

namespace gimbalsim::firmware {

/// truth with target_boresight and pointing_error at t = k T [s]. noexcept, no allocation.
inline contract::Truth observedTruth(contract::Truth truth, const pointing::TruthObserver& o, double t) noexcept {
  truth.pointing_error = o.observe(t, truth.boresight, truth.target_boresight);
  return truth;
}

}  // namespace gimbalsim::firmware
