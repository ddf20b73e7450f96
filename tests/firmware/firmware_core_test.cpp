// The firmware core in one process (no LCM, no threads): watchdog, command
// validation, saturation, quantization, one-tick latency, seeded noise, plant
// fault latching, lockstep determinism, and zero allocation per tick.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "alloc_guard.hpp"
#include "firmware_test_util.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "gimbalsim/firmware_sim/bench_tick.hpp"
#include "gimbalsim/firmware_sim/histogram.hpp"
#include "gimbalsim/firmware_sim/spsc_ring.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "test_util.hpp"

namespace gimbalsim::firmware {
namespace {

using test::g_allocations;
using test::setEigenMallocAllowed;

using test_helpers::Bench;
using test_helpers::benchScene;
using test_helpers::torqueCommand;

bool hasFault(const Status& s, Fault f) { return (s.faults & f) != 0; }

template <class V>
bool sameState(const State<V>& a, const State<V>& b) {
  return a.t == b.t && a.q == b.q && a.v == b.v;
}


TEST(FirmwareConfig, RefusesAPeriodThatIsNotAMultipleOfTheStep) {
  const PlantScene sc = benchScene();  // sim.step = 1 ms
  Config c;
  c.control_period = 1.5e-3;
  using Setting = ConfigCheck::Setting;
  const ConfigCheck err = checkConfig(sc.scene, c);
  EXPECT_EQ(err.wrong, Setting::ControlPeriod);
  EXPECT_NE(err.message.find("not a whole multiple of sim.step"), std::string::npos) << err.message;
  c.control_period = 0.5e-3;
  EXPECT_EQ(checkConfig(sc.scene, c).wrong, Setting::ControlPeriod);
  EXPECT_FALSE(checkConfig(sc.scene, c).message.empty());
  c.control_period = 3e-3;
  const ConfigCheck fine = checkConfig(sc.scene, c);
  EXPECT_TRUE(fine.ok());
  EXPECT_EQ(fine.message, "");
  EXPECT_EQ(fine.steps_per_tick, 3);
  // The one whole-multiple rule (isWholeMultiple): decimal spellings pass, a period 1e-10 off does not.
  c.control_period = 0.3 / 0.1 * 1e-3;
  EXPECT_TRUE(checkConfig(sc.scene, c).ok());
  c.control_period = 3e-3 * (1.0 + 1e-10);
  EXPECT_EQ(checkConfig(sc.scene, c).wrong, Setting::ControlPeriod);
  c.control_period = 3e-3;
  c.safe_torque = Vec2(0.0, 1e9);
  EXPECT_EQ(checkConfig(sc.scene, c).wrong, Setting::SafeTorque);
  EXPECT_NE(checkConfig(sc.scene, c).message.find("safe torque"), std::string::npos);
}

TEST(Firmware, SubStepsThePlantInsideEachTick) {
  // T = 4 sim.step: one tick must equal four plain steps with the same torque.
  const PlantScene sc = benchScene({"sim.step=2.5e-4"});
  Config c;
  c.control_period = 1e-3;
  Firmware<Bench> fw(sc, c);
  ASSERT_EQ(fw.stepsPerTick(), 4);
  fw.tick(0);
  fw.receive(torqueCommand(1, 0, 3.0, -2.0));
  fw.tick(1000);  // applies (3, -2) over [t1, t2]
  fw.tick(2000);
  const Model& m = sc.scene.model;
  Data<Bench> d(m);
  State<Bench> s = initialState<Bench>(sc.scene.run.initial);
  Input u;  // tick 0: zero torque (no command yet)
  for (int i = 0; i < 4; ++i) ASSERT_EQ(step(m, d, s, u).status, StepStatus::Ok);
  u.tau = Vec2(3.0, -2.0);
  for (int i = 0; i < 8; ++i) ASSERT_EQ(step(m, d, s, u).status, StepStatus::Ok);
  EXPECT_TRUE(sameState(s, fw.state())) << "t " << s.t << " vs " << fw.state().t;
}

TEST(Firmware, WatchdogTripsWithinItsBoundAndRecovers) {
  const PlantScene sc = benchScene();
  Config c;
  c.watchdog_timeout = 0.05;  // 50 ticks at 1 kHz
  Firmware<Bench> fw(sc, c);
  ASSERT_EQ(fw.watchdogTicks(), 50);
  std::int64_t seq = 0;
  const int last_cmd_tick = 100;  // the last valid command is taken at this tick
  for (int k = 0; k <= 400; ++k) {
    const bool sending = (k >= 1 && k <= last_cmd_tick) || k >= 300;
    if (sending) fw.receive(torqueCommand(++seq, k - 1, 1.0, 2.0));
    fw.tick(k * 1000);
    const Status& s = fw.status();
    const bool want_tripped = k > last_cmd_tick && k < 300 && k - last_cmd_tick >= 50;
    ASSERT_EQ(hasFault(s, kWatchdogTripped), want_tripped) << "tick " << k;
    if (want_tripped) {
      EXPECT_EQ(s.applied_torque[0], 0.0);
      EXPECT_EQ(s.applied_torque[1], 0.0);
    } else if (k >= 1) {
      // Between commands and before the trip the last command is held.
      EXPECT_EQ(s.applied_torque[0], 1.0) << "tick " << k;
      EXPECT_EQ(s.applied_torque[1], 2.0) << "tick " << k;
    }
  }
  EXPECT_EQ(fw.counters().watchdog_trips, 1);
  EXPECT_EQ(fw.counters().missed, 199);  // ticks 101..299
  EXPECT_EQ(fw.counters().rejected, 0);
}

TEST(Firmware, WatchdogTripsAtStartWhenNoControllerAnswers) {
  const PlantScene sc = benchScene();
  Config c;
  c.watchdog_timeout = 0.02;
  Firmware<Bench> fw(sc, c);
  for (int k = 0; k <= 25; ++k) {
    fw.tick(k * 1000);
    EXPECT_EQ(hasFault(fw.status(), kWatchdogTripped), k >= 20) << "tick " << k;
  }
}

TEST(Firmware, InvalidCommandsAreRejectedCountedFlaggedAndNeverReachThePlant) {
  const PlantScene sc = benchScene({"torque.limit=[2, 3]"});
  Config c;  // sanity range 10 x limit: 20, 30 N m
  struct Bad {
    Command cmd;
    Rejection why;
  };
  const double nan = std::nan(""), inf = INFINITY;
  // seq 1000000: if any of these were accepted, every later valid command
  // (seq < 1000000) would be stale and the dynamics would change.
  const std::int64_t big = 1000000;
  Command unknown_mode = torqueCommand(big, 9, 0.5, 0.5);
  unknown_mode.mode = 7;
  const std::vector<Bad> bads = {
      {torqueCommand(big, 9, nan, 0.0), Rejection::NonFinite},
      {torqueCommand(big, 9, 0.0, inf), Rejection::NonFinite},
      {torqueCommand(big, 9, -inf, 0.0), Rejection::NonFinite},
      {torqueCommand(big, 9, 20.5, 0.0), Rejection::OutOfRange},
      {torqueCommand(big, 9, 0.0, -30.5), Rejection::OutOfRange},
      {unknown_mode, Rejection::UnknownMode},
      {torqueCommand(5, 9, 0.7, 0.7), Rejection::StaleSeq},       // seq 5 <= last accepted 10
      {torqueCommand(10, 9, 0.7, 0.7), Rejection::StaleSeq},      // duplicate of the last accepted
      {torqueCommand(big, 11, 0.7, 0.7), Rejection::FutureStatus},  // newest status is 10
  };
  auto run = [&](bool inject, std::vector<Status>* statuses) {
    Firmware<Bench> fw(sc, c);
    for (int k = 0; k < 40; ++k) {
      if (k >= 1) {
        if (inject && k == 11) {
          for (const Bad& b : bads) EXPECT_EQ(fw.receive(b.cmd), b.why) << describe(b.why);
          fw.receiveUndecodable();
        }
        fw.receive(torqueCommand(k, k - 1, 0.1 * k, -0.05 * k));
      }
      fw.tick(k * 1000);
      statuses->push_back(fw.status());
    }
    return fw.state();
  };
  std::vector<Status> clean, dirty;
  const State<Bench> a = run(false, &clean);
  const State<Bench> b = run(true, &dirty);
  EXPECT_TRUE(sameState(a, b)) << "a rejected command changed the dynamics";
  for (std::size_t k = 0; k < clean.size(); ++k) {
    EXPECT_EQ(clean[k].applied_torque[0], dirty[k].applied_torque[0]) << "tick " << k;
    EXPECT_EQ(clean[k].applied_torque[1], dirty[k].applied_torque[1]) << "tick " << k;
    EXPECT_EQ(clean[k].last_command_seq, dirty[k].last_command_seq) << "tick " << k;
    EXPECT_EQ(hasFault(dirty[k], kCommandRejected), k == 11) << "tick " << k;
    EXPECT_FALSE(hasFault(clean[k], kCommandRejected));
  }
  const std::int64_t n_bad = static_cast<std::int64_t>(bads.size()) + 1;
  EXPECT_EQ(dirty.back().commands_rejected, n_bad);
  EXPECT_EQ(dirty.back().commands_received, clean.back().commands_received + n_bad);
  EXPECT_EQ(dirty[10].commands_rejected, 0);
  EXPECT_EQ(dirty[11].commands_rejected, n_bad);
  EXPECT_EQ(dirty.back().commands_missed, clean.back().commands_missed);
}

TEST(Firmware, RejectionCountsPerReason) {
  const PlantScene sc = benchScene();
  Firmware<Bench> fw(sc, Config{});
  fw.tick(0);
  Command bad_mode = torqueCommand(1, 0, 0, 0);
  bad_mode.mode = -1;
  fw.receive(bad_mode);
  fw.receive(torqueCommand(2, 0, std::nan(""), 0));
  fw.receive(torqueCommand(3, 0, 0, 0));  // valid
  fw.receive(torqueCommand(3, 0, 0, 0));  // duplicate
  fw.receiveUndecodable();
  const Counters& n = fw.counters();
  EXPECT_EQ(n.received, 5);
  EXPECT_EQ(n.rejected, 4);
  EXPECT_EQ(n.by_reason[static_cast<int>(Rejection::UnknownMode)], 1);
  EXPECT_EQ(n.by_reason[static_cast<int>(Rejection::NonFinite)], 1);
  EXPECT_EQ(n.by_reason[static_cast<int>(Rejection::StaleSeq)], 1);
  EXPECT_EQ(n.by_reason[static_cast<int>(Rejection::Undecodable)], 1);
  EXPECT_EQ(fw.lastAcceptedSeq(), 3);
}

TEST(Firmware, TorqueSaturatesAtTheMotorLimitWithTheFlag) {
  const PlantScene sc = benchScene({"torque.limit=[2, 3]"});
  Firmware<Bench> fw(sc, Config{});
  fw.tick(0);
  fw.receive(torqueCommand(1, 0, 1.5, -2.5));  // within the limit
  fw.tick(1000);
  EXPECT_FALSE(hasFault(fw.status(), kTorqueSaturated));
  EXPECT_EQ(fw.status().applied_torque[0], 1.5);
  EXPECT_EQ(fw.status().applied_torque[1], -2.5);
  fw.receive(torqueCommand(2, 1, 5.0, -7.0));  // beyond the limit, within the sanity range
  fw.tick(2000);
  EXPECT_TRUE(hasFault(fw.status(), kTorqueSaturated));
  EXPECT_EQ(fw.status().applied_torque[0], 2.0);
  EXPECT_EQ(fw.status().applied_torque[1], -3.0);
  EXPECT_EQ(fw.appliedInput().tau, Vec2(2.0, -3.0));
  EXPECT_EQ(fw.counters().motor_limited_ticks, 1);
  EXPECT_EQ(fw.counters().rejected, 0);
}

TEST(Firmware, EncoderAnglesAreMultiplesOfTheResolution) {
  const double res = 1e-3;  // coarse, so quantization is visible
  const PlantScene sc = benchScene({"sensors.encoder_resolution=1e-3"});
  Firmware<Bench> fw(sc, Config{});
  int differs = 0;
  for (int k = 0; k < 600; ++k) {
    if (k >= 1) fw.receive(torqueCommand(k, k - 1, 5.0, 5.0));
    const double true1 = fw.state().theta(0), true2 = fw.state().theta(1);
    fw.tick(k * 1000);
    for (int j = 0; j < 2; ++j) {
      const double a = fw.status().angle[j];
      EXPECT_NEAR(a / res, std::round(a / res), 1e-6) << "tick " << k << " axis " << j;
      EXPECT_LE(std::fabs(a - (j == 0 ? true1 : true2)), 0.5 * res * (1 + 1e-9)) << "tick " << k;
      if (a != (j == 0 ? true1 : true2)) ++differs;
    }
  }
  EXPECT_GT(fw.state().theta(0), 20 * res) << "the gimbal must move across many quanta";
  EXPECT_GT(differs, 100) << "quantization must change the reading";
}

TEST(Firmware, ASpatialJointsEncoderReadsThetaAndTheTruthCarriesItsTilt) {
  // paper_spatial2 without friction, torques that drive the journal into its
  // bearing: the encoder reads the spin theta only, while the truth carries
  // the tilt gamma of the journal axis z = Rot(x, alpha) Rot(y, beta) e_z =
  // (sin b, -sin a cos b, cos a cos b) and each end's force. gamma =
  // acos(cos a cos b), written as an atan2 so it keeps its digits near 0.
  using Spatial = Variant<true, ClearanceKind::Ideal, ClearanceKind::Spatial, false>;
  const double res = 1e-6;
  const PlantScene sc = test::plant("paper_spatial2", {"friction.law=none", "sensors.encoder_resolution=1e-6"});
  Firmware<Spatial> fw(sc, Config{});
  constexpr int qg = State<Spatial>::QJ + Spatial::G2;  // [p_x, p_y, alpha, beta, theta]
  double max_tilt = 0.0, max_fn = 0.0;
  int one_end = 0;
  for (int k = 0; k < 400; ++k) {
    if (k >= 1) fw.receive(torqueCommand(k, k - 1, 5.0, 10.0));
    const State<Spatial> x = fw.state();
    fw.tick(k * 1000);
    const Truth& t = fw.truth();
    ASSERT_EQ(t.joint_angle[1], x.q(qg + 4)) << "tick " << k;
    EXPECT_LE(std::fabs(fw.status().angle[1] - x.q(qg + 4)), 0.5 * res * (1 + 1e-9)) << "tick " << k;
    const double a = x.q(qg + 2), b = x.q(qg + 3);
    const double gamma = std::atan2(std::hypot(std::sin(b), std::sin(a) * std::cos(b)), std::cos(a) * std::cos(b));
    EXPECT_NEAR(t.tilt[1], gamma, 1e-15) << "tick " << k;
    EXPECT_EQ(t.tilt[0], 0.0);
    EXPECT_EQ(t.eccentricity[0], 0.0);
    EXPECT_EQ(t.end_normal_force[0] + t.end_normal_force[1], 0.0) << "joint 1 is ideal";
    EXPECT_NEAR(t.end_normal_force[2] + t.end_normal_force[3], t.contact_normal_force[1],
                1e-12 * (1.0 + t.contact_normal_force[1]));
    EXPECT_EQ(t.penetration[1], std::max(t.end_penetration[2], t.end_penetration[3]));
    if ((t.end_normal_force[2] > 0.0) != (t.end_normal_force[3] > 0.0)) ++one_end;
    max_tilt = std::max(max_tilt, t.tilt[1]), max_fn = std::max(max_fn, t.contact_normal_force[1]);
  }
  EXPECT_GT(max_tilt, 1e-3) << "the journal must tilt";
  EXPECT_GT(max_fn, 0.0) << "and touch its bearing";
  EXPECT_GT(one_end, 0) << "at one end alone";
}

// The truth takes every output column of the same name (truth_from_row.hpp):
// each such truth column has the Row column's unit, and after ticks of a
// scene whose spatial bearing carries load it holds exactly the value
// observe() gives for the same state. The columns it must cover are named
// here, so a list that loses one fails. (The shape is one this file already
// compiles: each new one costs minutes in the sanitizer build.)
TEST(Firmware, TruthCopiesEveryOutputColumnOfTheSameName) {
  std::vector<std::string> truth_cols;
  Truth probe;
  TruthFields::visit([&](Columns names, auto&) { truth_cols.insert(truth_cols.end(), names.begin(), names.end()); },
                     probe);
  int matched = 0;
  for (const std::string& c : truth_cols) {
    const int i = columnIndex(columnName(c));
    if (i < 0) continue;
    ++matched;
    EXPECT_EQ(c, std::string(kRowFields[i].name) + "[" + kRowFields[i].unit + "]") << "unit of " << c;
  }
  EXPECT_EQ(truthFromRow().count, matched);
  for (const char* must : {"base_x", "base_wz", "base_vy", "theta2", "dtheta1", "ecc1_x", "ecc2_y", "delta1", "fn2",
                           "ft1", "joint2_force", "tilt2", "delta2_plus", "fn1_minus", "bore_z", "mom_lx", "energy"}) {
    bool found = false;
    for (int k = 0; k < truthFromRow().count; ++k) found = found || kColumns[truthFromRow().slots[k].column] == std::string(must);
    EXPECT_TRUE(found) << must << " does not reach the truth";
  }
  using Spatial = Variant<true, ClearanceKind::Ideal, ClearanceKind::Spatial, false>;
  const PlantScene sc = test::plant("paper_spatial2", {"friction.law=none"});
  Firmware<Spatial> fw(sc, Config{});
  Data<Spatial> d(sc.scene.model);
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    if (k >= 1) fw.receive(torqueCommand(k, k - 1, 5.0, 10.0));
    fw.sample(k * 1000);
    const Row r = observe(sc.scene.model, d, fw.state(), fw.appliedInput());
    const Truth& t = fw.truth();
    const auto* base = reinterpret_cast<const char*>(&t);
    for (int j = 0; j < truthFromRow().count; ++j) {
      const auto& slot = truthFromRow().slots[j];
      ASSERT_EQ(*reinterpret_cast<const double*>(base + slot.offset), r.*slot.member)
          << kColumns[slot.column] << " at tick " << k;
      ++checked;
    }
    fw.advance();
  }
  EXPECT_GT(checked, 0);
}

TEST(Firmware, ACommandActsFromTheNextTickNotTheOneItArrivesIn) {
  const PlantScene sc = benchScene();
  const int k_change = 20;
  auto run = [&](bool change, std::vector<State<Bench>>* states, std::vector<Status>* st) {
    Firmware<Bench> fw(sc, Config{});
    for (int k = 0; k < 30; ++k) {
      states->push_back(fw.state());  // state at t_k
      fw.tick(k * 1000);
      st->push_back(fw.status());
      // The controller answers status k during tick k.
      const double tau = (change && k >= k_change) ? 4.0 : 1.0;
      fw.receive(torqueCommand(k + 1, k, tau, 0.0));
    }
  };
  std::vector<State<Bench>> sa, sb;
  std::vector<Status> ta, tb;
  run(false, &sa, &ta);
  run(true, &sb, &tb);
  // The new torque is sent during tick 20: status 20 still reports the old
  // torque, status 21 the new one; the state at t21 is untouched, t22 moved.
  EXPECT_EQ(tb[k_change].applied_torque[0], 1.0);
  EXPECT_EQ(tb[k_change + 1].applied_torque[0], 4.0);
  EXPECT_TRUE(sameState(sa[k_change + 1], sb[k_change + 1]));
  EXPECT_FALSE(sameState(sa[k_change + 2], sb[k_change + 2]));
  EXPECT_GT(sb[k_change + 2].dtheta(0), sa[k_change + 2].dtheta(0));
}

template <class V>
std::vector<Status> noisyRun(const PlantScene& sc, int ticks) {
  Firmware<V> fw(sc, Config{});
  std::vector<Status> out;
  for (int k = 0; k < ticks; ++k) {
    if (k >= 1) fw.receive(torqueCommand(k, k - 1, 0.2, 0.1));
    fw.tick(k * 1000);
    out.push_back(fw.status());
  }
  return out;
}

TEST(Firmware, SeededSensorNoiseIsReproducibleAndSeedDependent) {
  const std::vector<std::string> noise = {"sensors.encoder_noise=1e-4", "sensors.rate_noise=2e-3",
                                          "sensors.encoder_resolution=0"};
  auto with = [&](const char* seed) {
    std::vector<std::string> s = noise;
    s.push_back(seed);
    return benchScene(s);
  };
  const PlantScene sc7 = with("sensors.seed=7"), sc8 = with("sensors.seed=8");
  const auto a = noisyRun<Bench>(sc7, 2000), b = noisyRun<Bench>(sc7, 2000), c = noisyRun<Bench>(sc8, 2000);
  const auto clean = noisyRun<Bench>(benchScene({"sensors.encoder_resolution=0"}), 2000);
  int same_seed_diff = 0, other_seed_same = 0;
  double sum2_angle = 0.0, sum2_rate = 0.0, sum_rate = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    for (int j = 0; j < 2; ++j) {
      same_seed_diff += (a[k].angle[j] != b[k].angle[j]) + (a[k].rate[j] != b[k].rate[j]);
      other_seed_same += (a[k].angle[j] == c[k].angle[j]);
      // Noise-free plant (noise enters only the report): the difference is the noise.
      const double ea = a[k].angle[j] - clean[k].angle[j], er = a[k].rate[j] - clean[k].rate[j];
      sum2_angle += ea * ea;
      sum2_rate += er * er;
      sum_rate += er;
    }
  }
  EXPECT_EQ(same_seed_diff, 0);
  EXPECT_LT(other_seed_same, 10);
  const double n = 2.0 * a.size();
  // Sample standard deviation of 4000 normal deviates: within 5% of sigma
  // with overwhelming probability (its relative sd is 1/sqrt(2n) = 1.1%).
  EXPECT_NEAR(std::sqrt(sum2_angle / n), 1e-4, 5e-6);
  EXPECT_NEAR(std::sqrt(sum2_rate / n), 2e-3, 1e-4);
  EXPECT_NEAR(sum_rate / n, 0.0, 5 * 2e-3 / std::sqrt(n));
}

TEST(GaussianNoise, MomentsOfTheStandardNormal) {
  GaussianNoise g(42);
  const int n = 200000;
  double s1 = 0, s2 = 0, s4 = 0;
  int beyond2 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = g.normal();
    s1 += x, s2 += x * x, s4 += x * x * x * x;
    beyond2 += std::fabs(x) > 2.0;
  }
  EXPECT_NEAR(s1 / n, 0.0, 0.01);
  EXPECT_NEAR(s2 / n, 1.0, 0.01);
  EXPECT_NEAR(s4 / n, 3.0, 0.06);                   // kurtosis of a normal
  EXPECT_NEAR(beyond2 / double(n), 0.0455, 0.003);  // P(|x| > 2)
}

TEST(Firmware, PlantFaultLatchesFreezesTheStateAndNeverReportsBadNumbers) {
  // A sub-step cap too small for the first impact makes step() fail.
  const PlantScene sc = test::plant("paper_clearance", {"sim.max_substeps=3"});
  Firmware<FloatingClearanceFriction> fw(sc, Config{});
  int first_fault = -1;
  State<FloatingClearanceFriction> frozen;
  for (int k = 0; k < 3000 && first_fault < 0; ++k) {
    if (k >= 1) fw.receive(torqueCommand(k, k - 1, 5.0, 10.0));
    fw.tick(k * 1000);
    if (fw.plantFault()) {
      first_fault = k;
      frozen = fw.state();
    }
  }
  ASSERT_GE(first_fault, 0) << "the cap must stop the plant";
  EXPECT_EQ(fw.plantStatus(), StepStatus::SubstepCap);
  for (int k = first_fault + 1; k < first_fault + 20; ++k) {
    fw.receive(torqueCommand(k, k - 1, 5.0, 10.0));
    fw.tick(k * 1000);
    EXPECT_TRUE(hasFault(fw.status(), kPlantFault));
    EXPECT_TRUE(hasFault(Status{.faults = fw.truth().faults}, kPlantFault));
    EXPECT_TRUE(sameState(frozen, fw.state()));
    for (double x : fw.truth().boresight) EXPECT_TRUE(std::isfinite(x));
    EXPECT_TRUE(std::isfinite(fw.truth().contact_normal_force[1]));
    EXPECT_TRUE(std::isfinite(fw.status().angle[1]));
  }
}

TEST(Firmware, PointingErrorAgainstTheProfileTarget) {
  const PlantScene sc = benchScene();
  pointing::TargetProfile p;
  p.start = Vec2(0.1, 0.0);  // the gimbal rests at (0, 0): 0.1 rad off in azimuth
  p.slew_start = 10.0;
  // The plant knows no target: the truth observer measures against the profile.
  Firmware<Bench> fw(sc, Config{});
  fw.tick(0);
  EXPECT_EQ(fw.truth().pointing_error, 0.0);
  const pointing::TruthObserver with(sc.scene.model, &p, fw.initialBoresight());
  EXPECT_NEAR(observedTruth(fw.truth(), with, 0.0).pointing_error, 0.1, 1e-12);
  const pointing::TruthObserver none(sc.scene.model, nullptr, fw.initialBoresight());
  EXPECT_EQ(observedTruth(fw.truth(), none, 0.0).pointing_error, 0.0);  // target = the initial boresight
}

template <class V>
std::vector<Truth> lockstepRun(const PlantScene& sc, int ticks) {
  // The core as the lockstep loop drives it: status k -> a PD law -> command
  // answering k -> tick k+1.
  Firmware<V> fw(sc, Config{});
  std::vector<Truth> out;
  for (int k = 0; k < ticks; ++k) {
    fw.tick(k * 1000);
    out.push_back(fw.truth());
    const Status& s = fw.status();
    const double t1 = 30.0 * (0.3 - s.angle[0]) - 20.0 * s.rate[0];
    const double t2 = 60.0 * (0.2 - s.angle[1]) - 30.0 * s.rate[1];
    fw.receive(torqueCommand(k + 1, k, t1, t2));
  }
  return out;
}

TEST(Firmware, LockstepCoreRunsAreBitForBitRepeatable) {
  const PlantScene sc = test::plant("paper_clearance", {"sensors.encoder_noise=1e-5", "sensors.rate_noise=1e-4"});
  const auto a = lockstepRun<FloatingClearanceFriction>(sc, 400);
  const auto b = lockstepRun<FloatingClearanceFriction>(sc, 400);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(std::memcmp(&a[k], &b[k], sizeof(Truth)), 0) << "tick " << k;
  }
  EXPECT_GT(std::fabs(a.back().joint_angle[0]), 1e-3) << "the run must do something";
}

TEST(Firmware, TickAndReceiveAllocateNothingAfterWarmUp) {
  test::noteIfNotCheckedBuild();
  // Every sensor on: encoders, and the attitude sensors with noise, bias walk, latency and an outage.
  const PlantScene sc = test::plant(
      "paper_clearance", {"sensors.encoder_noise=1e-5", "sensors.rate_noise=1e-4", "sensors.star_tracker_rate=50",
                          "sensors.star_tracker_noise=1e-4", "sensors.star_tracker_latency=0.035",
                          "sensors.star_tracker_outage=[0.2, 0.25]", "sensors.gyro_bias=[1e-3, -2e-3, 5e-4]",
                          "sensors.gyro_bias_walk=1e-4", "sensors.gyro_noise=1e-3"});
  pointing::TargetProfile p;
  Firmware<FloatingClearanceFriction> fw(sc, Config{});
  const pointing::TruthObserver observer(sc.scene.model, &p, fw.initialBoresight());
  std::int64_t seq = 0;
  for (int k = 0; k < 10; ++k) {
    fw.receive(torqueCommand(++seq, k - 1, 5.0, 10.0));
    fw.tick(k * 1000);
  }
  // The hand-over rings of the real-time loop, in the same window.
  SpscRing<Command> in(64);
  SpscRing<Truth> out(64);
  int star_samples = 0;
  const long long before = g_allocations.load();
  setEigenMallocAllowed(false);
  for (int k = 10; k < 400; ++k) {
    ASSERT_TRUE(in.push(torqueCommand(++seq, k - 1, 5.0, 10.0)));
    Command c;
    while (in.pop(c)) fw.receive(c);
    if (k % 50 == 0) {
      fw.receive(torqueCommand(seq, k - 1, std::nan(""), 0.0));
      fw.receiveUndecodable();
    }
    fw.sample(k * 1000, true);
    ASSERT_TRUE(out.push(observedTruth(fw.truth(), observer, k * 1e-3)));
    star_samples += fw.attitude().star_valid;
    fw.advance();
    Truth t;
    ASSERT_TRUE(out.pop(t));
  }
  setEigenMallocAllowed(true);
  EXPECT_EQ(g_allocations.load() - before, 0) << "heap allocations in 390 ticks";
  EXPECT_EQ(star_samples, 15) << "samples of 0 .. 0.36 s delivered 35 ms later, less the 4 lost to the outage";
  EXPECT_FALSE(fw.plantFault());
  EXPECT_GT(fw.counters().max_substeps_in_tick, 1) << "the window must cover contact sub-stepping";
  // The count firmware_sim's worst-case bound multiplies: never exceeded (one step per tick here).
  const Model& m = sc.scene.model;
  EXPECT_GT(fw.counters().max_derivatives_in_tick, 4);
  EXPECT_LE(fw.counters().max_derivatives_in_tick,
            static_cast<long long>(substepCap(m)) * derivativesPerUnit<FloatingClearanceFriction>(m));
}

TEST(Histogram, QuantilesOfAKnownDistribution) {
  Histogram h(1000);
  for (int i = 0; i < 1000; ++i) h.add(i + 0.5);  // one sample per bin, 0.5 .. 999.5 us
  h.add(5000.0);                                   // overflow
  EXPECT_EQ(h.count(), 1001u);
  EXPECT_NEAR(h.quantile(0.5), 501.0, 1.0);
  EXPECT_NEAR(h.quantile(0.99), 991.0, 1.0);
  EXPECT_EQ(h.quantile(1.0), 5000.0);
  EXPECT_EQ(h.max(), 5000.0);
  Histogram empty(10);
  EXPECT_EQ(empty.quantile(0.5), 0.0);
}

TEST(SpscRing, KeepsOrderAndRefusesWhenFull) {
  SpscRing<int> r(4);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(r.push(i));
  EXPECT_FALSE(r.push(99));
  int x = -1;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(r.pop(x));
    EXPECT_EQ(x, i);
  }
  EXPECT_FALSE(r.pop(x));
  EXPECT_TRUE(r.push(5));
  EXPECT_TRUE(r.pop(x));
  EXPECT_EQ(x, 5);
}

}  // namespace
}  // namespace gimbalsim::firmware
