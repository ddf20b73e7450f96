// The fault schedule (fault_schedule.hpp, fault_schedule_io.hpp) and where
// each fault enters the firmware core (firmware.hpp), in one process: the
// YAML reader's refusals name file:line:column and the key; every kind does
// what README "Fault schedule" says, at the ticks it says, flagged in status
// and truth; probabilistic faults follow their seed; a run with faults is
// bit for bit repeatable and allocates nothing per tick.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "alloc_guard.hpp"
#include "firmware_test_util.hpp"
#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "test_util.hpp"

namespace gimbalsim::firmware {
namespace {

const std::string kDemo = std::string(GIMBALSIM_SOURCE_DIR) + "/tools/faults/demo.yaml";
const std::string kTrackerDemo = std::string(GIMBALSIM_SOURCE_DIR) + "/tools/faults/tracker.yaml";

using test_helpers::Bench;
using test_helpers::benchScene;
using test_helpers::torqueCommand;

/// The refusal text of a schedule (all problems, one per line); "" if accepted.
std::string refusal(const std::string& yaml) {
  try {
    loadFaultScheduleText(yaml, "f.yaml");
  } catch (const FaultScheduleError& e) {
    std::string s;
    for (const std::string& p : e.problems()) s += p + "\n";
    return s;
  }
  return "";
}

FaultSchedule schedule(const std::string& yaml) { return loadFaultScheduleText(yaml, "test"); }


TEST(FaultScheduleFile, TheDemoSchedulesLoadWithEveryKind) {
  const FaultSchedule s = loadFaultSchedule(kDemo);
  EXPECT_EQ(s.seed, 7u);
  const FaultSchedule tracker = loadFaultSchedule(kTrackerDemo);  // the kinds that need the antenna's sensors
  ASSERT_EQ(s.faults.size() + tracker.faults.size(), static_cast<std::size_t>(kNumFaultKinds));
  std::vector<bool> seen(kNumFaultKinds, false);
  for (const FaultSpec& f : s.faults) seen[static_cast<int>(f.kind)] = true;
  for (const FaultSpec& f : tracker.faults) seen[static_cast<int>(f.kind)] = true;
  for (int k = 0; k < kNumFaultKinds; ++k) EXPECT_TRUE(seen[k]) << faultTypeName(static_cast<FaultKind>(k));
  EXPECT_EQ(s.faults[0].kind, FaultKind::EncoderNoise);
  EXPECT_EQ(s.faults[0].axis, 0);
  EXPECT_EQ(s.faults[0].value, 2.0e-5);
  EXPECT_GT(s.faults[0].line, 4);
  EXPECT_TRUE(checkFaultsAgainstScene(s, test::plant("paper_clearance"), kDemo).empty());
  EXPECT_TRUE(checkFaultsAgainstScene(tracker, test::plant("paper_spatial2_tracker"), kTrackerDemo).empty());
  // a scene without the antenna's sensors has no tracker for them to act on
  const auto none = checkFaultsAgainstScene(tracker, test::plant("paper_clearance"), kTrackerDemo);
  ASSERT_EQ(none.size(), 3u);
  EXPECT_NE(none[0].find("(tracker_outage): the scene has no tracker to act on (scene key sensors.antenna is none)"),
            std::string::npos) << none[0];
}

TEST(FaultScheduleFile, RefusalsNameLineColumnEntryAndKey) {
  EXPECT_NE(refusal("faults:\n  - {type: encoder_stuk, axis: azimuth}\n")
                .find("f.yaml:2:12: fault #1: key 'type': expected one of encoder_dropout |"),
            std::string::npos)
      << refusal("faults:\n  - {type: encoder_stuk, axis: azimuth}\n");
  EXPECT_NE(refusal("faults:\n  - type: encoder_stuck\n    start: 1\n")
                .find("f.yaml:2:5: fault #1 (encoder_stuck): key 'axis' is missing"),
            std::string::npos);
  EXPECT_NE(refusal("faults:\n  - {type: status_drop, probability: 1.5}\n")
                .find("f.yaml:2:38: fault #1 (status_drop): key 'probability': must be in (0, 1]"),
            std::string::npos)
      << refusal("faults:\n  - {type: status_drop, probability: 1.5}\n");
  EXPECT_NE(refusal("faults:\n  - {type: status_delay, ticks: 0}\n").find("key 'ticks': must be in [1, 1000] ticks, got 0"),
            std::string::npos);
  EXPECT_NE(refusal("faults:\n  - {type: status_delay}\n").find("key 'ticks' is missing"), std::string::npos);
  EXPECT_NE(refusal("faults:\n  - {type: command_drop, start: 2, end: 1}\n")
                .find("fault #1 (command_drop): key 'end': must be > start, got 1 (start 2)"),
            std::string::npos);
  EXPECT_NE(refusal("faults:\n  - {type: motor_failure, axis: elevation, limit: 3}\n")
                .find("f.yaml:2:44: fault #1 (motor_failure): unknown key 'limit' (motor_failure takes type, start, end, "
                      "axis, probability)"),
            std::string::npos)
      << refusal("faults:\n  - {type: motor_failure, axis: elevation, limit: 3}\n");
  EXPECT_NE(refusal("faults:\n  - {type: bearing_wear, start: 1, clearance: 1e-3}\n")
                .find("key 'end' is missing (the wear grows over [start, end])"),
            std::string::npos);
  EXPECT_NE(refusal("faults:\n  - {type: friction_rise, mu: 0.5, probability: 0.5}\n").find("unknown key 'probability'"),
            std::string::npos);
  EXPECT_NE(refusal("faults:\n  - {type: gyro_bias_jump, bias: [1, 2]}\n").find("key 'bias': expected [x, y, z] in rad/s"),
            std::string::npos)
      << refusal("faults:\n  - {type: gyro_bias_jump, bias: [1, 2]}\n");
  EXPECT_NE(refusal("seed: -1\n").find("f.yaml:1:7: key 'seed': must be >= 0"), std::string::npos) << refusal("seed: -1\n");
  EXPECT_NE(refusal("sead: 1\n").find("f.yaml:1:1: unknown key 'sead'"), std::string::npos);
  // (pass 107) a key holding U+202E was printed raw (the line ran backwards): raw in the file it is refused at its
  // place; from a quoted key's escape it is shown by its code point, in the schedule's and a fault's unknown keys
  const std::string raw = refusal("note\u202e: 1\n");
  EXPECT_NE(raw.find("f.yaml:1:5: character U+202E splits or reorders the line"), std::string::npos) << raw;
  for (const std::string& text : {std::string("\"no\\u202ete\": 1\n"),
                                   std::string("faults:\n  - {type: status_drop, \"no\\u202ete\": 1}\n")}) {
    const std::string shown = refusal(text);
    EXPECT_NE(shown.find("unknown key 'no<U+202E>te'"), std::string::npos) << shown;
    EXPECT_EQ(shown.find("\u202e"), std::string::npos) << shown;
  }
  // (pass 52) a key given twice: the last was kept without a word, where a scene refuses it at its second place
  EXPECT_NE(refusal("seed: 1\nseed: 2\n").find("f.yaml:2:1: key 'seed': given twice (first at f.yaml:1:1)"),
            std::string::npos)
      << refusal("seed: 1\nseed: 2\n");
  const std::string twice = refusal("faults:\n  - {type: status_drop, start: 1, start: 2}\n");
  EXPECT_NE(twice.find("f.yaml:2:35: fault #1 (status_drop): key 'start': given twice (first at f.yaml:2:25)"),
            std::string::npos)
      << twice;
  EXPECT_NE(refusal("faults: {type: status_drop}\n").find("key 'faults': must be a list of faults"), std::string::npos);
  EXPECT_NE(refusal("faults: [\n").find("f.yaml:"), std::string::npos);
  EXPECT_NE(refusal("faults: [\n").find("not valid YAML"), std::string::npos);
  EXPECT_NE(refusal("- 1\n").find("must be a mapping with keys seed and faults"), std::string::npos);
  // The bounded reader: a second document is refused, not silently ignored.
  EXPECT_NE(refusal("seed: 1\n---\nseed: 2\n").find("more than one YAML document"), std::string::npos)
      << refusal("seed: 1\n---\nseed: 2\n");
  // Ranges the plant and the controller honour (a huge gyro bias jump made the loop's commands NaN).
  EXPECT_NE(refusal("faults:\n  - {type: gyro_bias_jump, bias: [1e300, 0, 0]}\n")
                .find("key 'bias': must be in [-1, 1] rad/s (each axis), got 1e+300"),
            std::string::npos)
      << refusal("faults:\n  - {type: gyro_bias_jump, bias: [1e300, 0, 0]}\n");
  EXPECT_NE(refusal("faults:\n  - {type: encoder_bias, axis: azimuth, bias: 1e308}\n")
                .find("key 'bias': must be in [-100, 100] rad, got 1e+308"),
            std::string::npos);
  EXPECT_NE(refusal("faults:\n  - {type: status_drop, end: 1e300}\n").find("key 'end': must be in [0, 1e+09] s"),
            std::string::npos);
  // Every problem of a file at once.
  const std::string two = refusal("faults:\n  - {type: status_drop, start: -1}\n  - {type: torque_limit, axis: up, limit: 1}\n");
  EXPECT_NE(two.find("fault #1 (status_drop): key 'start': must be in [0, 1e+09] s, got -1"), std::string::npos) << two;
  EXPECT_NE(two.find("f.yaml:3:32: fault #2 (torque_limit): key 'axis': expected one of azimuth | elevation, got 'up'"),
            std::string::npos)
      << two;
  std::string many = "faults:\n";
  for (int i = 0; i <= kMaxFaults; ++i) many += "  - {type: status_drop}\n";
  EXPECT_NE(refusal(many).find("f.yaml:2:3: key 'faults': at most 256 faults (every tick evaluates each), got 257"),
            std::string::npos)
      << refusal(many).substr(0, 200);
  EXPECT_EQ(refusal("seed: 3\nfaults: []\n"), "");
}

TEST(FaultScheduleFile, SceneChecksNameTheLineAndTheSceneKey) {
  const FaultSchedule wear = schedule("faults:\n  - {type: bearing_wear, start: 1, end: 2, clearance: 0.4e-3}\n");
  const auto on_ideal = checkFaultsAgainstScene(wear, test::plant("paper_ideal"), "w.yaml");
  ASSERT_EQ(on_ideal.size(), 1u);
  // each at its place, the column too (pass 63): the entry's, or its parameter's value
  EXPECT_NE(on_ideal[0].find("w.yaml:2:5: fault #1 (bearing_wear): needs a joint with clearance"), std::string::npos)
      << on_ideal[0];
  const auto below = checkFaultsAgainstScene(wear, test::plant("paper_clearance"), "w.yaml");
  ASSERT_EQ(below.size(), 1u);
  EXPECT_NE(below[0].find("w.yaml:2:55: fault #1 (bearing_wear): key 'clearance': must be above joint2's clearance "
                          "0.0005"),
            std::string::npos)
      << below[0];
  const FaultSchedule rise = schedule("faults:\n  - {type: friction_rise, start: 1, mu: 0.5}\n");
  EXPECT_EQ(checkFaultsAgainstScene(rise, test::plant("paper_clearance", {"friction.law=none"}), "r.yaml").size(), 1u);
  EXPECT_TRUE(checkFaultsAgainstScene(rise, test::plant("paper_clearance"), "r.yaml").empty());
}

// (pass 89) On a fixed base the star tracker reads the identity and a perfect gyro zero: an outage changed no
// estimate while it was flagged as injected. Noise or a bias on either sensor, or a gyro_bias_jump acting before
// the outage's next sample, and it can act (fault_response_test.cpp shows both); a jump after the outage's next
// sample or after the run's end let it through (passes 90-91).
TEST(FaultScheduleFile, AStarTrackerOutageOnAFixedBaseWithPerfectSensorsIsRefused) {
  const PlantScene fixed = test::plant("paper_ideal", {"structure.base=fixed"});
  const auto check = [](const std::string& yaml, const PlantScene& ps) {
    return checkFaultsAgainstSamples(schedule(yaml), ps, 0.5, 1e-3, "o.yaml", false);  // 0.5 s at 1 kHz, 10 Hz tracker
  };
  const std::string outage = "faults:\n  - {type: star_tracker_outage, start: 0.1, end: 0.2}\n";
  const auto refused = check(outage, fixed);
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_NE(refused[0].find("o.yaml:2:5: fault #1 (star_tracker_outage): on a fixed base (scene key structure.base "
                            "fixed)"),
            std::string::npos)
      << refused[0];
  EXPECT_NE(refused[0].find("change no estimate"), std::string::npos) << refused[0];
  EXPECT_TRUE(check(outage, test::plant("paper_ideal")).empty());
  for (const char* imperfect : {"sensors.gyro_noise=1e-6", "sensors.gyro_bias=[0, 1e-6, 0]",
                                "sensors.gyro_bias_walk=1e-7", "sensors.star_tracker_noise=1e-5"}) {
    EXPECT_TRUE(check(outage, test::plant("paper_ideal", {"structure.base=fixed", imperfect})).empty()) << imperfect;
  }
  // a jump before the outage, or inside it, or by its next sample (0.2 s): the estimate can drift
  for (const char* start : {"0.05", "0.15", "0.2"}) {
    EXPECT_TRUE(check(outage + "  - {type: gyro_bias_jump, start: " + start + ", bias: [0, 0, 1e-5]}\n", fixed).empty())
        << start;
  }
  // after the outage's next sample (pass 93: 0.25 s was let through), or after the run's end: it changes nothing
  for (const char* start : {"0.25", "0.45", "5"}) {
    EXPECT_EQ(check(outage + "  - {type: gyro_bias_jump, start: " + start + ", bias: [0, 0, 1e-5]}\n", fixed).size(),
              1u)
        << start;
  }
}

// (pass 90) A sample taken in an outage is lost only if it would have been delivered within the run: an outage
// whose one sample falls due after the run's end (latency 0.15 s) changed nothing but its flag.
TEST(FaultScheduleFile, AStarTrackerOutageWhoseSampleWouldArriveAfterTheRunIsRefused) {
  const std::string outage = "faults:\n  - {type: star_tracker_outage, start: 0.86, end: 0.95}\n";
  const auto check = [&](const char* latency, bool last_tick_acts = false) {  // 1 s at 1 kHz, a 10 Hz tracker:
    return checkFaultsAgainstSamples(schedule(outage), test::plant("paper_ideal", {latency}), 1.0, 1e-3, "o.yaml",
                                     last_tick_acts);  // the sample at 0.9 s is taken in it
  };
  const auto late = check("sensors.star_tracker_latency=0.15");
  ASSERT_EQ(late.size(), 1u);
  EXPECT_NE(late[0].find("[0.86, 0.95) s takes and delivers no star tracker sample"), std::string::npos) << late[0];
  EXPECT_TRUE(check("sensors.star_tracker_latency=0").empty());
  // the 0.8 s sample falls due at 0.9 s, in it: dropped (its own, due at 1.0 s, the run's last tick, aside)
  EXPECT_TRUE(check("sensors.star_tracker_latency=0.1").empty());
  EXPECT_EQ(check("sensors.star_tracker_latency=0.15", true).size(), 1u) << "due after the run, in closed_loop too";
}

// (pass 97) The boresight tracker's window faults between two of its 100 Hz samples (0.01 and 0.02 s) touched
// none, flagged as injected all the same, as the star tracker's outage did (pass 87): an outage or a dropout drops
// no delivery there, a bias biases no reading taken; each refused, naming what it misses, and each taken once the
// window holds a take (the outage, the bias) or a delivery (the outage, the dropout).
TEST(FaultScheduleFile, ABoresightTrackerWindowBetweenTwoSamplesIsRefused) {
  const PlantScene ps =
      test::plant("paper_spatial2_tracker", {"sensors.tracker_rate=100", "sensors.tracker_latency=0.005"});
  const auto check = [&](const std::string& entry) {  // 0.1 s at 1 kHz: takes at 0.01 k, deliveries 5 ms later
    return checkFaultsAgainstSamples(schedule("faults:\n  - " + entry + "\n"), ps, 0.1, 1e-3, "o.yaml", false);
  };
  const auto outage = check("{type: tracker_outage, start: 0.016, end: 0.019}");
  ASSERT_EQ(outage.size(), 1u);
  EXPECT_NE(outage[0].find("fault #1 (tracker_outage): [0.016, 0.019) s takes and delivers no boresight tracker "
                           "sample (one every 0.01 s, sensors.tracker_rate; latency 0.005 s)"),
            std::string::npos)
      << outage[0];
  const auto dropout = check("{type: tracker_dropout, start: 0.011, end: 0.014}");
  ASSERT_EQ(dropout.size(), 1u);
  EXPECT_NE(dropout[0].find("s has no delivery of a boresight tracker sample"), std::string::npos) << dropout[0];
  const auto bias = check("{type: tracker_bias, start: 0.011, end: 0.019, bias: [1e-3, 0]}");
  ASSERT_EQ(bias.size(), 1u);
  EXPECT_NE(bias[0].find("s takes no boresight tracker sample"), std::string::npos) << bias[0];
  // a take at 0.02 s (the outage, the bias), a delivery at 0.015 s (the outage, the dropout): they act
  EXPECT_TRUE(check("{type: tracker_outage, start: 0.016, end: 0.021}").empty());
  EXPECT_TRUE(check("{type: tracker_outage, start: 0.011, end: 0.016}").empty());
  EXPECT_TRUE(check("{type: tracker_dropout, start: 0.014, end: 0.016}").empty());
  EXPECT_TRUE(check("{type: tracker_bias, start: 0.019, end: 0.021, bias: [1e-3, 0]}").empty());
  EXPECT_EQ(check("{type: tracker_bias, start: 0.011, end: 0.016, bias: [1e-3, 0]}").size(), 1u)
      << "a delivery but no take in it: the bias reaches no reading";
  // (pass 103) its one take, at 0.09 s, falls due at 0.1 s, the run's last tick: on the bench no command answers
  // it; closed_loop's last row records the estimate it moves
  const PlantScene late =
      test::plant("paper_spatial2_tracker", {"sensors.tracker_rate=100", "sensors.tracker_latency=0.01"});
  const auto bias_at_the_end = [&](bool last_tick_acts) {
    return checkFaultsAgainstSamples(schedule("faults:\n  - {type: tracker_bias, start: 0.085, end: 0.095, "
                                              "bias: [1e-3, 0]}\n"),
                                     late, 0.1, 1e-3, "o.yaml", last_tick_acts);
  };
  EXPECT_EQ(bias_at_the_end(false).size(), 1u);
  EXPECT_TRUE(bias_at_the_end(true).empty());
}

// (pass 79) A fault whose parameter changes nothing ran and was flagged as injected in every tick of its window:
// a bias of 0, a torque limit at or above the motor's, a friction rise to the scene's own mu.
TEST(FaultScheduleFile, AFaultThatWouldChangeNothingIsRefused) {
  for (const char* entry : {"{type: encoder_bias, axis: elevation, bias: 0}", "{type: gyro_bias_jump, bias: [0, 0, 0]}",
                            "{type: tracker_bias, bias: [0.0, -0.0]}"}) {
    const std::string why = refusal(std::string("faults:\n  - ") + entry + "\n");
    EXPECT_NE(why.find("key 'bias': a bias of 0"), std::string::npos) << entry << ": " << why;
    EXPECT_NE(why.find("the fault would act on nothing"), std::string::npos) << why;
  }
  EXPECT_EQ(refusal("faults:\n  - {type: gyro_bias_jump, bias: [0, 0, 1e-6]}\n"), "") << "one axis acts";
  const PlantScene clearance = test::plant("paper_clearance", {"torque.limit=[20, 10]"});
  const auto limit = checkFaultsAgainstScene(
      schedule("faults:\n  - {type: torque_limit, axis: elevation, start: 1, end: 2, limit: 10}\n"), clearance,
      "l.yaml");
  ASSERT_EQ(limit.size(), 1u);
  EXPECT_NE(limit[0].find("l.yaml:2:68: fault #1 (torque_limit): key 'limit': 10 N m is not below the elevation "
                          "motor's limit (scene key torque.limit, 10 N m)"),
            std::string::npos)
      << limit[0];
  EXPECT_TRUE(checkFaultsAgainstScene(
                  schedule("faults:\n  - {type: torque_limit, axis: azimuth, start: 1, end: 2, limit: 10}\n"),
                  clearance, "l.yaml")
                  .empty());
  const auto rise = checkFaultsAgainstScene(schedule("faults:\n  - {type: friction_rise, start: 1, mu: 0.25}\n"),
                                            test::plant("paper_clearance"), "r.yaml");
  ASSERT_EQ(rise.size(), 1u);
  EXPECT_NE(rise[0].find("key 'mu': 0.25 is joint2's friction.mu already"), std::string::npos) << rise[0];
}

/// Runs the bench scene with a constant command (answered every tick) and
/// the schedule; statuses, truths and the delivered flags per tick.
struct Trace {
  std::vector<Status> status;
  std::vector<bool> delivered;
  std::vector<Truth> truth;
  std::vector<Attitude> attitude;
  std::vector<Vec2> tau_true;
  Counters n;
};
template <class V = Bench>
Trace run(const PlantScene& sc, const FaultSchedule* f, int ticks, double tau1 = 2.0, double tau2 = 1.0) {
  Firmware<V> fw(sc, Config{}, f);
  Trace t;
  for (int k = 0; k < ticks; ++k) {
    fw.tick(k * 1000);
    t.status.push_back(fw.status());
    t.delivered.push_back(fw.statusDelivered());
    t.truth.push_back(fw.truth());
    t.attitude.push_back(fw.attitude());
    t.tau_true.push_back(fw.appliedInput().tau);
    fw.receive(torqueCommand(k + 1, k, tau1, tau2));
  }
  t.n = fw.counters();
  return t;
}

TEST(FaultInjection, StuckEncoderHoldsItsAngleWhileTheRateSensorWorks) {
  const PlantScene sc = benchScene();
  const FaultSchedule f = schedule("faults:\n  - {type: encoder_stuck, axis: elevation, start: 0.1, end: 0.2}\n");
  const Trace clean = run(sc, nullptr, 300), t = run(sc, &f, 300);
  const std::int64_t bit = injectedBit(FaultKind::EncoderStuck, 1);
  for (int k = 0; k < 300; ++k) {
    const bool active = k >= 100 && k < 200;
    EXPECT_EQ(t.status[k].injected_faults, active ? bit : 0) << k;
    EXPECT_EQ(t.truth[k].injected_faults, active ? bit : 0) << k;
    EXPECT_EQ(t.status[k].angle[0], clean.status[k].angle[0]) << "the other axis is untouched, tick " << k;
    EXPECT_EQ(t.status[k].rate[1], clean.status[k].rate[1]) << "the rate sensor still works, tick " << k;
    EXPECT_EQ(t.status[k].angle[1], active ? clean.status[100].angle[1] : clean.status[k].angle[1]) << k;
  }
  EXPECT_GT(clean.status[199].angle[1] - clean.status[100].angle[1], 5e-4) << "the axis moves while its encoder sticks";
}

TEST(FaultInjection, DropoutRepeatsTheLastAngleAndRate) {
  const PlantScene sc = benchScene();
  const FaultSchedule f = schedule("faults:\n  - {type: encoder_dropout, axis: azimuth, start: 0.05, end: 0.06}\n");
  const Trace clean = run(sc, nullptr, 80), t = run(sc, &f, 80);
  for (int k = 50; k < 60; ++k) {
    EXPECT_EQ(t.status[k].angle[0], clean.status[49].angle[0]) << k;
    EXPECT_EQ(t.status[k].rate[0], clean.status[49].rate[0]) << k;
    EXPECT_EQ(t.status[k].angle[1], clean.status[k].angle[1]) << k;
  }
  EXPECT_EQ(t.status[60].angle[0], clean.status[60].angle[0]);
  EXPECT_NE(clean.status[59].rate[0], clean.status[49].rate[0]);
}

TEST(FaultInjection, BiasStepAndNoiseBurstOnTheEncoder) {
  const PlantScene sc = benchScene({"sensors.encoder_resolution=0"});
  const FaultSchedule f = schedule(
      "seed: 3\nfaults:\n  - {type: encoder_bias, axis: azimuth, start: 0.01, bias: 1e-3}\n"
      "  - {type: encoder_noise, axis: elevation, start: 0.02, end: 0.52, sigma: 1e-4}\n");
  const Trace clean = run(sc, nullptr, 600), t = run(sc, &f, 600);
  double sum2 = 0.0;
  for (int k = 0; k < 600; ++k) {
    EXPECT_NEAR(t.status[k].angle[0] - clean.status[k].angle[0], k >= 10 ? 1e-3 : 0.0, 1e-15) << k;
    const double n = t.status[k].angle[1] - clean.status[k].angle[1];
    if (k >= 20 && k < 520) sum2 += n * n;
    else EXPECT_EQ(n, 0.0) << k;
  }
  EXPECT_NEAR(std::sqrt(sum2 / 500), 1e-4, 0.15e-4) << "burst sigma";
  const Trace again = run(sc, &f, 600);
  for (int k = 0; k < 600; ++k) EXPECT_EQ(again.status[k].angle[1], t.status[k].angle[1]) << "seeded, tick " << k;
}

TEST(FaultInjection, StatusDelayDeliversOldStatusesAndDropDeliversNone) {
  const PlantScene sc = benchScene();
  const FaultSchedule f = schedule(
      "faults:\n  - {type: status_delay, start: 0.01, end: 0.03, ticks: 4}\n  - {type: status_drop, start: 0.05, end: 0.053}\n");
  const Trace t = run(sc, &f, 70);
  for (int k = 0; k < 70; ++k) {
    if (k < 10 || (k >= 30 && k < 50) || k >= 53) {
      EXPECT_TRUE(t.delivered[k]) << k;
      EXPECT_EQ(t.status[k].seq, k) << k;
    } else if (k < 14) {
      EXPECT_FALSE(t.delivered[k]) << "status 10 is due at 14, tick " << k;
    } else if (k < 30) {
      EXPECT_TRUE(t.delivered[k]) << k;
      EXPECT_EQ(t.status[k].seq, k - 4) << k;
      EXPECT_EQ(t.status[k].injected_faults, injectedBit(FaultKind::StatusDelay, -1)) << "flags of its own tick";
    } else {
      EXPECT_FALSE(t.delivered[k]) << "dropped, tick " << k;
    }
    EXPECT_EQ(t.truth[k].seq, k) << "truth is never delayed";
  }
  // At 30 the delay ends: status 30 goes at once and supersedes 26..29, still held.
  EXPECT_EQ(t.n.bus.status_delayed, 20);
  EXPECT_EQ(t.n.bus.status_dropped, 3 + 4);
}

TEST(FaultInjection, CommandsLostOrLateOnTheBus) {
  const PlantScene sc = benchScene();
  const FaultSchedule drop = schedule("faults:\n  - {type: command_drop, start: 0.02, end: 0.025}\n");
  const FaultSchedule late = schedule("faults:\n  - {type: command_delay, start: 0.02, end: 0.021, ticks: 3}\n");
  for (const FaultSchedule* f : {&drop, &late}) {
    Firmware<Bench> fw(sc, Config{}, f);
    std::vector<double> applied;
    for (int k = 0; k < 40; ++k) {
      fw.tick(k * 1000);
      applied.push_back(fw.status().applied_torque[0]);
      fw.receive(torqueCommand(k + 1, k, 1.0 + k, 0.0));  // torque = 1 + the status answered
    }
    for (int k = 1; k < 40; ++k) {
      double want = k;  // the answer to status k - 1
      if (f == &drop && k >= 21 && k <= 25) want = 20;  // answers 20..24 were lost: the last one held
      if (f == &late && k >= 21 && k <= 23) want = 20;  // answer 20 is held 3 ticks, then acts at 24 ...
      if (f == &late && k == 24) want = 24;             // ... superseded at once by the newer 23
      EXPECT_EQ(applied[k], want) << (f == &drop ? "drop" : "delay") << ", tick " << k;
    }
    EXPECT_EQ(fw.counters().bus.commands_dropped, f == &drop ? 5 : 0);
    EXPECT_EQ(fw.counters().rejected, 0);
  }
}

TEST(FaultInjection, TorqueLimitAndMotorFailure) {
  const PlantScene sc = benchScene();
  const FaultSchedule f = schedule(
      "faults:\n  - {type: torque_limit, axis: azimuth, start: 0.01, end: 0.02, limit: 0.5}\n"
      "  - {type: motor_failure, axis: elevation, start: 0.03, end: 0.04}\n");
  const Trace t = run(sc, &f, 50, 2.0, -1.0), clean = run(sc, nullptr, 50, 2.0, -1.0);
  for (int k = 1; k < 50; ++k) {
    const bool limited = k >= 10 && k < 20, failed = k >= 30 && k < 40;
    EXPECT_EQ(t.status[k].applied_torque[0], limited ? 0.5 : 2.0) << k;
    EXPECT_EQ((t.status[k].faults & kTorqueSaturated) != 0, limited) << k;
    // A failed motor: the firmware commands the torque (status), the motor gives none (truth, physics).
    EXPECT_EQ(t.status[k].applied_torque[1], -1.0) << k;
    EXPECT_EQ(t.truth[k].applied_torque[1], failed ? 0.0 : -1.0) << k;
    EXPECT_EQ(t.tau_true[k](1), failed ? 0.0 : -1.0) << k;
  }
  // Without its motor the elevation axis is hardly accelerated (only through the azimuth's coupling).
  const double dw = t.truth[40].joint_rate[1] - t.truth[30].joint_rate[1];
  const double dw_clean = clean.truth[40].joint_rate[1] - clean.truth[30].joint_rate[1];
  EXPECT_LT(std::fabs(dw), 0.1 * std::fabs(dw_clean)) << dw << " vs " << dw_clean;
}

TEST(FaultInjection, StarTrackerOutageAndGyroBiasJumpInTheAttitudeMessage) {
  const PlantScene sc = test::plant("paper_ideal", {"sensors.star_tracker_rate=100"});
  const FaultSchedule f = schedule(
      "faults:\n  - {type: star_tracker_outage, start: 0.1, end: 0.2}\n"
      "  - {type: gyro_bias_jump, start: 0.15, bias: [1e-3, 0, -2e-3]}\n");
  const Trace clean = run<FloatingIdeal>(sc, nullptr, 300), t = run<FloatingIdeal>(sc, &f, 300);
  int samples_in_outage = 0;
  for (int k = 0; k < 300; ++k) {
    const bool outage = k >= 100 && k < 200;
    EXPECT_EQ(t.attitude[k].star_outage, outage ? 1 : 0) << k;
    if (outage) samples_in_outage += t.attitude[k].star_valid;
    else EXPECT_EQ(t.attitude[k].star_valid, clean.attitude[k].star_valid) << k;
    EXPECT_NEAR(t.attitude[k].gyro_rate[0] - clean.attitude[k].gyro_rate[0], k >= 150 ? 1e-3 : 0.0, 1e-15) << k;
    EXPECT_NEAR(t.attitude[k].gyro_rate[2] - clean.attitude[k].gyro_rate[2], k >= 150 ? -2e-3 : 0.0, 1e-15) << k;
  }
  EXPECT_EQ(samples_in_outage, 0);
  EXPECT_EQ(t.truth[120].injected_faults, injectedBit(FaultKind::StarTrackerOutage, -1));
  EXPECT_EQ(t.truth[160].injected_faults,
            injectedBit(FaultKind::StarTrackerOutage, -1) | injectedBit(FaultKind::GyroBiasJump, -1));
}

TEST(FaultInjection, BearingWearAndFrictionRiseChangeOnlyTheFirmwaresModelCopy) {
  const PlantScene sc = test::plant("paper_clearance", {"structure.base=fixed"});
  const FaultSchedule f = schedule(
      "faults:\n  - {type: bearing_wear, start: 0.1, end: 0.3, clearance: 0.9e-3}\n"
      "  - {type: friction_rise, start: 0.2, mu: 0.6}\n");
  Firmware<FixedClearanceFriction> fw(sc, Config{}, &f);
  const double c0 = sc.scene.model.bearing[1].clearance, mu0 = sc.scene.model.bearing[1].mu;
  for (int k = 0; k < 400; ++k) {
    fw.tick(k * 1000);
    fw.receive(torqueCommand(k + 1, k, 3.0, 6.0));
    const double t = k * 1e-3;
    const double want_c = c0 + std::clamp((t - 0.1) / 0.2, 0.0, 1.0) * (0.9e-3 - c0);
    const ContactParams& cp = fw.model().bearing[1];
    ASSERT_NEAR(cp.clearance, want_c, 1e-15) << k;
    ASSERT_EQ(cp.mu, k >= 200 ? 0.6 : mu0) << k;
    // The wear is the journal's; K as Model::finalize derives it.
    Model m = sc.scene.model;
    m.bearing[1].journal_radius = m.bearing[1].bearing_radius - cp.clearance;
    m.finalize();
    ASSERT_NEAR(cp.K, m.bearing[1].K, 1e-12 * m.bearing[1].K) << k;
    ASSERT_NEAR(cp.journal_radius, m.bearing[1].journal_radius, 1e-18);
  }
  EXPECT_EQ(sc.scene.model.bearing[1].clearance, c0) << "the scene's Model is never touched";
  EXPECT_FALSE(fw.plantFault());
  EXPECT_EQ(fw.truth().injected_faults, injectedBit(FaultKind::BearingWear, -1) | injectedBit(FaultKind::FrictionRise, -1));
}

TEST(FaultSchedule, BearingFaultsAreCheckedAgainstTheBearingTheyActOn) {
  // Joint 1's bearing is 5 mm in radius, joint 2's (ideal) the default 10 mm:
  // a wear to 9.9 mm would put joint 1's journal outside its bearing.
  const PlantScene planar1 =
      test::plant("paper_planar1", {"joint1.contact.bearing_radius=5e-3", "joint1.contact.journal_radius=4.5e-3"});
  const FaultSchedule wear = schedule("faults:\n  - {type: bearing_wear, start: 1, end: 2, clearance: 9.9e-3}\n");
  const auto p = checkFaultsAgainstScene(wear, planar1, "w.yaml");
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].find("below joint1.contact.bearing_radius 0.005 m"), std::string::npos) << p[0];
  // With an axis it acts on that joint's bearing only, which must have clearance.
  const FaultSchedule on_azimuth =
      schedule("faults:\n  - {type: bearing_wear, axis: azimuth, start: 1, end: 2, clearance: 0.8e-3}\n");
  const auto ideal_axis = checkFaultsAgainstScene(on_azimuth, test::plant("paper_clearance"), "w.yaml");
  ASSERT_EQ(ideal_axis.size(), 1u);
  // at the axis's own line and column (pass 63)
  EXPECT_NE(ideal_axis[0].find("w.yaml:2:32: fault #1 (bearing_wear): key 'axis': the azimuth joint is ideal (scene "
                               "key structure.joint1)"),
            std::string::npos)
      << ideal_axis[0];
  EXPECT_TRUE(checkFaultsAgainstScene(on_azimuth, test::plant("paper_planar1"), "w.yaml").empty());
  // Friction rise needs a friction law on the bearing it acts on.
  const FaultSchedule rise = schedule("faults:\n  - {type: friction_rise, axis: elevation, start: 1, mu: 0.5}\n");
  const auto no_law = checkFaultsAgainstScene(
      rise, test::plant("paper_both_planar", {"joint2.friction.law=none"}), "r.yaml");
  ASSERT_EQ(no_law.size(), 1u);
  EXPECT_NE(no_law[0].find("joint2.friction.law is none"), std::string::npos) << no_law[0];
  // Worn, a spatial bearing must stay at least 4 clearances long, as the scene's own clearance
  // must (a 2.5 mm bearing worn to 9.9 mm tilted its journal 73 degrees, and the run said ok).
  const PlantScene short_spatial = test::plant("paper_spatial2", {"contact.bearing_length=2.5e-3"});
  const auto too_short = checkFaultsAgainstScene(wear, short_spatial, "w.yaml");
  ASSERT_EQ(too_short.size(), 1u);
  EXPECT_NE(too_short[0].find("w.yaml:2:55: fault #1 (bearing_wear): key 'clearance': a spatial bearing must be at least 4 "
                              "clearances long: joint2.contact.bearing_length 0.0025 m against 4 x 0.0099 m"),
            std::string::npos)
      << too_short[0];
  EXPECT_TRUE(checkFaultsAgainstScene(wear, test::plant("paper_spatial2"), "w.yaml").empty())
      << "a 50 mm bearing takes a 9.9 mm clearance";
}

TEST(FaultInjection, BearingWearRampsEachBearingFromItsOwnClearance) {
  // Two planar bearings of different clearance: a wear without an axis ramps
  // each from its own value; one with an axis only its own.
  const PlantScene sc = test::plant("paper_both_planar", {"structure.base=fixed", "joint1.contact.clearance=2e-4"});
  const double c1 = sc.scene.model.bearing[0].clearance, c2 = sc.scene.model.bearing[1].clearance;
  ASSERT_NEAR(c1, 2e-4, 1e-15);
  ASSERT_NEAR(c2, 5e-4, 1e-15);
  const FaultSchedule both = schedule("faults:\n  - {type: bearing_wear, start: 0.1, end: 0.3, clearance: 0.9e-3}\n");
  const FaultSchedule elevation =
      schedule("faults:\n  - {type: bearing_wear, axis: elevation, start: 0.1, end: 0.3, clearance: 0.9e-3}\n");
  using V = GIMBALSIM_SHAPE(false, Planar, Planar, true);
  Firmware<V> fw_both(sc, Config{}, &both), fw_elev(sc, Config{}, &elevation);
  for (int k = 0; k < 400; ++k) {
    for (Firmware<V>* fw : {&fw_both, &fw_elev}) {
      fw->tick(k * 1000);
      fw->receive(torqueCommand(k + 1, k, 3.0, 6.0));
    }
    const double x = std::clamp((k * 1e-3 - 0.1) / 0.2, 0.0, 1.0);
    ASSERT_NEAR(fw_both.model().bearing[0].clearance, c1 + x * (0.9e-3 - c1), 1e-15) << k;
    ASSERT_NEAR(fw_both.model().bearing[1].clearance, c2 + x * (0.9e-3 - c2), 1e-15) << k;
    ASSERT_EQ(fw_elev.model().bearing[0].clearance, c1) << k;
    ASSERT_NEAR(fw_elev.model().bearing[1].clearance, c2 + x * (0.9e-3 - c2), 1e-15) << k;
  }
  EXPECT_EQ(fw_elev.truth().injected_faults, injectedBit(FaultKind::BearingWear, 1));
}

TEST(FaultInjection, ProbabilisticFaultsFollowTheirSeed) {
  const PlantScene sc = benchScene();
  auto ticks = [&](int seed) {
    const FaultSchedule f = schedule("seed: " + std::to_string(seed) +
                                     "\nfaults:\n  - {type: status_drop, start: 0.1, end: 2.1, probability: 0.25}\n");
    const Trace t = run(sc, &f, 2200);
    std::vector<bool> dropped;
    for (int k = 0; k < 2200; ++k) {
      EXPECT_EQ(t.truth[k].injected_faults != 0, !t.delivered[k]) << "flagged exactly when dropped, tick " << k;
      dropped.push_back(!t.delivered[k]);
    }
    return dropped;
  };
  const auto a = ticks(11), b = ticks(11), c = ticks(12);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  long long n = 0;
  for (int k = 0; k < 2200; ++k) {
    if (k < 100 || k >= 2100) EXPECT_FALSE(a[k]) << k;
    n += a[k];
  }
  // Binomial(2000, 0.25): mean 500, sd 19.4; 5 sd either side.
  EXPECT_GT(n, 403);
  EXPECT_LT(n, 597);
}

TEST(FaultInjection, ARunWithEveryFaultIsRepeatableAndAllocatesNothingPerTick) {
  test::noteIfNotCheckedBuild();
  const PlantScene sc = test::plant("paper_clearance", {"sensors.star_tracker_rate=50", "sensors.gyro_noise=1e-4",
                                                         "sensors.antenna=tracker_gyro"});
  // The demo schedule moved into the first 0.4 s, probabilities included.
  const FaultSchedule f = schedule(
      "seed: 5\nfaults:\n"
      "  - {type: encoder_noise, axis: azimuth, start: 0.02, end: 0.1, sigma: 2.0e-5}\n"
      "  - {type: encoder_bias, axis: elevation, start: 0.03, end: 0.2, bias: 1.0e-4}\n"
      "  - {type: status_drop, start: 0.05, end: 0.3, probability: 0.2}\n"
      "  - {type: status_delay, start: 0.06, end: 0.09, ticks: 5}\n"
      "  - {type: command_drop, start: 0.1, end: 0.2, probability: 0.3}\n"
      "  - {type: command_delay, start: 0.15, end: 0.25, ticks: 3}\n"
      "  - {type: encoder_stuck, axis: azimuth, start: 0.12, end: 0.2}\n"
      "  - {type: encoder_dropout, axis: elevation, start: 0.2, end: 0.25}\n"
      "  - {type: torque_limit, axis: azimuth, start: 0.22, end: 0.3, limit: 2}\n"
      "  - {type: motor_failure, axis: elevation, start: 0.26, end: 0.3}\n"
      "  - {type: star_tracker_outage, start: 0.1, end: 0.2}\n"
      "  - {type: gyro_bias_jump, start: 0.1, bias: [0, 0, 2.0e-5]}\n"
      "  - {type: bearing_wear, start: 0.05, end: 0.35, clearance: 0.8e-3}\n"
      "  - {type: friction_rise, start: 0.1, end: 0.3, mu: 0.4}\n"
      "  - {type: tracker_outage, start: 0.1, end: 0.15}\n"
      "  - {type: tracker_bias, start: 0.2, bias: [1.0e-4, -2.0e-4]}\n"
      "  - {type: tracker_dropout, start: 0.3, end: 0.35, probability: 0.5}\n");
  auto go = [&](bool guard, std::vector<Truth>* truths, std::vector<Status>* statuses) {
    Firmware<FloatingClearanceFriction> fw(sc, Config{}, &f);
    std::int64_t seq = 0;
    for (int k = 0; k < 10; ++k) {
      fw.receive(torqueCommand(++seq, k - 1, 5.0, 10.0));
      fw.tick(k * 1000);
    }
    const long long before = test::g_allocations.load();
    if (guard) test::setEigenMallocAllowed(false);
    for (int k = 10; k < 400; ++k) {
      fw.receive(torqueCommand(++seq, fw.statusDelivered() ? fw.status().seq : k - 2, 5.0, 10.0));
      fw.sample(k * 1000, true);
      if (truths != nullptr) {
        truths->push_back(fw.truth());
        statuses->push_back(fw.status());
      }
      fw.advance();
    }
    if (guard) {
      test::setEigenMallocAllowed(true);
      EXPECT_EQ(test::g_allocations.load() - before, 0) << "heap allocations in 390 ticks with every fault";
    }
    EXPECT_FALSE(fw.plantFault()) << describe(fw.plantStatus());
    EXPECT_GT(fw.counters().fault_ticks, 300);
  };
  go(true, nullptr, nullptr);
  std::vector<Truth> a, b;
  std::vector<Status> sa, sb;
  go(false, &a, &sa);
  go(false, &b, &sb);
  ASSERT_EQ(a.size(), b.size());
  std::int64_t all = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(std::memcmp(&a[k], &b[k], sizeof(Truth)), 0) << "tick " << k;
    ASSERT_EQ(std::memcmp(&sa[k], &sb[k], sizeof(Status)), 0) << "tick " << k;
    all |= a[k].injected_faults;
  }
  for (int kind = 0; kind < kNumFaultKinds; ++kind) {
    EXPECT_NE(all & (std::int64_t{3} << (2 * kind)), 0) << faultTypeName(static_cast<FaultKind>(kind)) << " never flagged";
  }
}

// (passes 103, 105) an outage short of the run's end may still lose every sample that would act: a 10 Hz star
// tracker in a 0.2 s run acts through its samples at 0 and 0.1 s (the one at 0.2 s, the last tick, answers none)
TEST(FaultSamples, AnOutageLosesEverySampleOnlyWhenNoneThatActsIsLeft) {
  const SampledSensor star{"star tracker", "sensors.star_tracker", 10.0, 0.0};
  EXPECT_TRUE(windowLosesEverySample(star, 0.0, 0.15, 0.2, 1e-3));
  EXPECT_FALSE(windowLosesEverySample(star, 0.0, 0.05, 0.2, 1e-3));   // the sample at 0.1 s acts
  EXPECT_FALSE(windowLosesEverySample(star, 0.05, 0.2, 0.2, 1e-3));   // the one at 0 s acts
  const SampledSensor late{"star tracker", "sensors.star_tracker", 10.0, 0.05};  // due at 0.05 and 0.15 s
  EXPECT_TRUE(windowLosesEverySample(late, 0.04, 0.06, 0.12, 1e-3));  // 0.1 s taken, due 0.15 s: after the run
  EXPECT_FALSE(windowLosesEverySample(star, 0.0, 0.15, 0.2, 0.0));    // no period: not judged
}

}  // namespace
}  // namespace gimbalsim::firmware
