// update() makes no heap allocation and throws nothing: a counting global
// operator new, and Eigen's malloc guard in the checked build.
#include <gtest/gtest.h>

#include <type_traits>

#include "alloc_guard.hpp"
#include "gimbalsim/controllers/config.hpp"

namespace gimbalsim::controllers {
namespace {

static_assert(noexcept(update(std::declval<const ControllerConfig&>(), std::declval<ControllerState&>(),
                              std::declval<const Measurement&>())));
static_assert(noexcept(std::declval<const TargetProfile&>().at(0.0)));

TEST(ControllerNoAlloc, TheCounterSeesAllocations) {
  EXPECT_GE(test::probeAllocations(), 1);
}

TEST(ControllerNoAlloc, UpdateAllocatesNothingInAnySegmentOrMode) {
  const ControllerConfig base = loadControllerConfig(std::string(GIMBALSIM_CONTROLLER_CONFIG_DIR) + "/default.yaml");
  for (auto rs : {RateSource::Status, RateSource::Difference}) {
    for (auto aw : {AntiWindup::None, AntiWindup::Clamping, AntiWindup::BackCalculation}) {
      ControllerConfig c = base;
      c.rate_source = rs;
      c.anti_windup = aw;
      ControllerState s;
      const long long before = test::g_allocations.load();
      test::setEigenMallocAllowed(false);
      double sink = 0.0;
      for (int k = 0; k < 10000; ++k) {  // 10 s: wait, slew, hold and track
        Measurement m;
        m.t = k * c.period;
        m.theta = {0.001 * k * c.period, 0.0};
        sink += update(c, s, m).tau.sum();
      }
      test::setEigenMallocAllowed(true);
      EXPECT_EQ(test::g_allocations.load() - before, 0);
      EXPECT_TRUE(std::isfinite(sink));
    }
  }
}

}  // namespace
}  // namespace gimbalsim::controllers
