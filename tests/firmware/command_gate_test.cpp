// Command acceptance that no single spoofed packet can subvert
// (command_gate.hpp, Firmware::receive): binding to the first valid
// command's source until the watchdog time, seq per source, no lock-out by an
// extreme seq, and rejected commands changing nothing in the plant.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "gimbalsim/firmware_sim/command_gate.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "firmware_test_util.hpp"

namespace gimbalsim::firmware {
namespace {

constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
constexpr SourceId kReal = 0x7f000001'1f40, kSpoof = 0x7f000001'2710;
using V = CommandGate::Verdict;

TEST(CommandGate, TheFirstAcceptedCommandBindsItsSourceUntilTheBindingTimesOut) {
  CommandGate g(50);
  EXPECT_FALSE(g.bound());
  EXPECT_EQ(g.check(kReal, 0, 0), V::Accept);
  g.accept(kReal, 0, 0);
  EXPECT_EQ(g.check(kSpoof, 5, 1), V::WrongSource);
  EXPECT_EQ(g.check(kSpoof, 5, 50), V::WrongSource) << "the watchdog trips at tick 50: still bound before it";
  EXPECT_EQ(g.check(kSpoof, 5, 51), V::Accept) << "once the watchdog has tripped, the binding is over";
  EXPECT_EQ(g.check(kReal, 1, 10), V::Accept);
  g.accept(kReal, 1, 10);
  EXPECT_EQ(g.check(kSpoof, 5, 60), V::WrongSource) << "each accepted command renews the binding";
}

TEST(CommandGate, SeqIsCheckedAgainstTheBoundSourceOnly) {
  CommandGate g(50);
  g.accept(kReal, 100, 0);
  EXPECT_EQ(g.check(kReal, 100, 1), V::StaleSeq);
  EXPECT_EQ(g.check(kReal, 99, 1), V::StaleSeq);
  EXPECT_EQ(g.check(kReal, kMin, 1), V::StaleSeq);
  EXPECT_EQ(g.check(kReal, 101, 1), V::Accept);
  // A stranger's extreme seq is refused for its source, never recorded.
  EXPECT_EQ(g.check(kSpoof, kMax, 1), V::WrongSource);
  EXPECT_EQ(g.lastSeq(), 100);
  EXPECT_EQ(g.check(kReal, 101, 2), V::Accept);
}

TEST(CommandGate, AnExtremeSeqLocksNobodyOutLongerThanTheBinding) {
  CommandGate g(50);
  g.accept(kReal, kMax, 0);  // the bound source itself sent INT64_MAX (a bug)
  EXPECT_EQ(g.check(kReal, 7, 50), V::StaleSeq);
  EXPECT_EQ(g.check(kReal, 7, 51), V::Accept) << "a new binding starts a fresh seq history";
  EXPECT_EQ(g.check(kReal, 0, 51), V::Accept);
  EXPECT_EQ(g.check(kReal, -1, 51), V::StaleSeq) << "seq starts at 0";
}

TEST(CommandGate, CheckChangesNothing) {
  CommandGate g(3);
  g.accept(kReal, 5, 0);
  for (int i = 0; i < 100; ++i) g.check(kSpoof, kMax - i, 1);
  EXPECT_EQ(g.source(), kReal);
  EXPECT_EQ(g.lastSeq(), 5);
  EXPECT_EQ(g.check(kReal, 6, 2), V::Accept);
}

// The firmware: the shared bench plant and command builder (firmware_test_util.hpp).
using test_helpers::benchScene;
using test_helpers::Bench;
constexpr auto cmd = test_helpers::torqueCommand;

TEST(CommandAcceptance, ASpoofedExtremeSeqFromAnotherSourceNeverLocksOutTheController) {
  const PlantScene sc = benchScene();
  Config c;  // 1 kHz, watchdog 50 ms
  Firmware<Bench> fw(sc, c);
  fw.tick(0);
  ASSERT_EQ(fw.receive(cmd(0, 0, 1.0, 1.0), kReal), Rejection::None);
  fw.tick(1000);
  EXPECT_EQ(fw.receive(cmd(kMax, 0, 9.0, 9.0), kSpoof), Rejection::WrongSource);
  EXPECT_EQ(fw.receive(cmd(1, 1, 2.0, 2.0), kReal), Rejection::None) << "the controller goes on with its own seq";
  fw.tick(2000);
  EXPECT_DOUBLE_EQ(fw.status().applied_torque[0], 2.0);
  EXPECT_EQ(fw.status().last_command_seq, 1);
  EXPECT_EQ(fw.counters().by_reason[static_cast<int>(Rejection::WrongSource)], 1);
}

TEST(CommandAcceptance, AfterTheWatchdogTripsANewSourceIsAccepted) {
  const PlantScene sc = benchScene();
  Config c;
  Firmware<Bench> fw(sc, c);
  fw.tick(0);
  ASSERT_EQ(fw.receive(cmd(0, 0, 1.0, 1.0), kReal), Rejection::None);
  for (int k = 1; k <= 50; ++k) fw.tick(k * 1000);  // the controller died after tick 0
  EXPECT_FALSE(fw.watchdogTripped());
  EXPECT_EQ(fw.receive(cmd(0, 50, 0.5, 0.5), kSpoof), Rejection::WrongSource) << "still within the watchdog time";
  fw.tick(51000);
  EXPECT_TRUE(fw.watchdogTripped());
  EXPECT_EQ(fw.receive(cmd(0, 51, 0.5, 0.5), kSpoof), Rejection::None) << "a replacement controller binds afresh";
  fw.tick(52000);
  EXPECT_FALSE(fw.watchdogTripped());
  EXPECT_DOUBLE_EQ(fw.status().applied_torque[0], 0.5);
}

TEST(CommandAcceptance, RejectedCommandsChangeNothingInThePlant) {
  // Two firmwares get the same valid commands; one also gets every kind of
  // rejected command in between. Their states must stay identical bit for
  // bit, and the applied torque too; only the counters and the flag differ.
  const PlantScene sc = benchScene();
  Config c;
  Firmware<Bench> clean(sc, c), attacked(sc, c);
  const double nan = std::nan("");
  for (std::int64_t k = 0; k < 200; ++k) {
    clean.tick(k * 1000);
    attacked.tick(k * 1000);
    const Command good = cmd(k, k, 0.01 * static_cast<double>(k % 7), -0.02);
    ASSERT_EQ(clean.receive(good, kReal), Rejection::None);
    if (k % 5 == 0 && k > 0) {  // (before the first valid command, a spoof would bind: see the README)
      EXPECT_EQ(attacked.receive(cmd(kMax, k, 5.0, 5.0), kSpoof), Rejection::WrongSource);
      EXPECT_EQ(attacked.receive(cmd(k + 1, k, nan, 0.0), kReal), Rejection::NonFinite);
      EXPECT_EQ(attacked.receive(cmd(k + 1, kMax, 1.0, 0.0), kReal), Rejection::FutureStatus);
      EXPECT_EQ(attacked.receive(cmd(k + 1, k, 1e12, 0.0), kReal), Rejection::OutOfRange);
    }
    ASSERT_EQ(attacked.receive(good, kReal), Rejection::None);
    if (k % 5 == 1) EXPECT_EQ(attacked.receive(good, kReal), Rejection::StaleSeq);  // a replay
    ASSERT_EQ(clean.state().q, attacked.state().q) << "tick " << k;
    ASSERT_EQ(clean.state().v, attacked.state().v) << "tick " << k;
    ASSERT_EQ(clean.appliedInput().tau, attacked.appliedInput().tau) << "tick " << k;
  }
  EXPECT_EQ(attacked.counters().rejected, 39 * 4 + 40);
  EXPECT_EQ(clean.counters().rejected, 0);
  EXPECT_EQ(attacked.counters().watchdog_trips, 0);
}

}  // namespace
}  // namespace gimbalsim::firmware
