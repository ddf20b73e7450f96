// A stranger that commands the plant before its controller (the plant binds
// the first valid command's source, command_gate.hpp) and leaves INT64_MAX as
// the plant's last accepted seq: the controller, answering every status with
// answerStatus as pointing_controller does, takes the plant back once the
// stranger's binding lapses, and keeps it. Its seq is its own counter; a
// controller that followed the status's last_command_seq would send INT64_MAX
// for ever after and be refused as stale at every tick.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>

#include "gimbalsim/controllers/answer.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "test_util.hpp"

namespace gimbalsim::controllers {
namespace {

constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
constexpr firmware::SourceId kController = 0x7f000001'1f40, kStranger = 0x7f000001'2710;

TEST(AnswerStatus, CommandSeqIsTheControllersOwnCounterWhateverTheStatusSays) {
  const ControllerConfig c = loadControllerConfig(std::string(GIMBALSIM_CONTROLLER_CONFIG_DIR) + "/default.yaml");
  ControllerState s;
  std::int64_t next_seq = 0;
  const std::int64_t reported[] = {-1, 40, kMax, kMax - 1, 2, -1};
  for (std::int64_t k = 0; k < 6; ++k) {
    contract::Status st;
    st.seq = k;
    st.last_command_seq = reported[k];
    const Answer a = answerStatus(c, s, st, contract::Attitude{}, next_seq);
    EXPECT_EQ(a.cmd.seq, k) << "status " << k << " reported last_command_seq " << reported[k];
    EXPECT_EQ(a.cmd.status_seq, k);
  }
  EXPECT_EQ(next_seq, 6);
}

TEST(StrangerBinding, TheControllerTakesThePlantBackWhenTheStrangersBindingLapsesAndKeepsIt) {
  const firmware::PlantScene sc = test::plant("paper_ideal", {"structure.base=fixed"});
  firmware::Config fc;  // 1 kHz, watchdog 50 ms: a binding lasts 50 ticks after its last accepted command
  firmware::Firmware<FixedIdeal> fw(sc, fc);
  const ControllerConfig c = loadControllerConfig(std::string(GIMBALSIM_CONTROLLER_CONFIG_DIR) + "/default.yaml");
  ControllerState s;
  std::int64_t next_seq = 0;
  // The stranger sends seq INT64_MAX every 10 ticks up to tick 119; the
  // controller joins at tick 100 and answers every status from then on.
  constexpr int kStrangerEnd = 120, kControllerStart = 100, kTicks = 1000;
  int refused_after_lapse = 0, first_accepted = -1, controller_stale = 0;
  bool stranger_bound = false;
  for (int k = 0; k < kTicks; ++k) {
    fw.tick(1000LL * k);
    const contract::Status st = fw.status();
    stranger_bound |= st.last_command_seq == kMax;
    if (k < kStrangerEnd && k % 10 == 0) {
      contract::Command spoof;
      spoof.seq = kMax;
      spoof.status_seq = st.seq;
      spoof.mode = contract::kModeTorque;
      fw.receive(spoof, kStranger);
    }
    if (k < kControllerStart) continue;
    contract::Attitude att;
    att.seq = st.seq;
    const Answer a = answerStatus(c, s, st, att, next_seq);
    const firmware::Rejection r = fw.receive(a.cmd, kController);
    controller_stale += r == firmware::Rejection::StaleSeq;
    if (first_accepted >= 0 && r != firmware::Rejection::None) ++refused_after_lapse;
    if (r == firmware::Rejection::None && first_accepted < 0) first_accepted = k;
  }
  ASSERT_TRUE(stranger_bound) << "the stranger never held the plant: the test proves nothing";
  // The stranger bound at tick 0 and again at 60 (its binding of tick 0 had
  // lapsed after tick 50); its spoofs at 70..110 were refused as stale.
  EXPECT_GT(first_accepted, kControllerStart) << "the stranger's binding held the controller off";
  EXPECT_LE(first_accepted, kControllerStart + 51) << "for one watchdog time at most";
  EXPECT_EQ(refused_after_lapse, 0) << "the controller lost the plant again";
  EXPECT_FALSE(fw.watchdogTripped());
  EXPECT_LT(fw.status().last_command_seq, kTicks) << "the controller's own seq";
  EXPECT_EQ(controller_stale, 0) << "the controller never sent a seq at or below the plant's history";
}

}  // namespace
}  // namespace gimbalsim::controllers
