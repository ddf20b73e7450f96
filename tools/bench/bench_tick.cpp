// The LCM bench tick's fixed work, part by part (Google Benchmark): what
// firmware_sim's lockstep loop does each tick besides stepping the plant.
// One call of each benchmark is one occurrence of the part in a tick:
//   BM_ClockRead/0, /1         CLOCK_MONOTONIC, CLOCK_THREAD_CPUTIME_ID
//   BM_Encode<T>               one message into the send buffer
//   BM_Publish<T>/peers        encode + send of one message (lcm_wire's
//                              sender, a system call of its own) on a
//                              loopback-only udpm URL with 0..2 receiving
//                              sockets on its port (the plant's own, filtered
//                              to commands; a controller's, filtered to status
//                              and attitude)
//   BM_PublishTick/peers       a lockstep tick's attitude, status and truth
//                              staged and sent in one system call (as firmware_sim)
//   BM_ReceiveCommand          a command sent, then read (waitDrain) + reassemble
//   BM_Tick/scene/truth        BenchTick::sample + advance: firmware, sensors,
//                              the plant's step, and with truth = 1 the truth
//                              with its pointing error (the difference: truth)
// Not measurable in one process: waking a sleeping peer (the other process's
// CPU), which the lockstep run's wall time per tick holds.
//
//   build/bin/gimbalsim_bench_tick --benchmark_repetitions=9
//   /usr/bin/python3 tools/bench/tick_parts.py [--results]   # table, page
//
// Scene files: GIMBALSIM_SCENE_DIR (environment), else tools/scenes from the working directory.
// The URL: GIMBALSIM_BENCH_LCM_URL, else a ttl=0 group on port 7697.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <ctime>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "scene_once.hpp"
#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/firmware_sim/bench_tick.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/gimbal_attitude_t.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/lcm_wire/udpm_sender.hpp"

#ifndef GIMBALSIM_SCENE_DIR
#define GIMBALSIM_SCENE_DIR "tools/scenes"
#endif

namespace {

using namespace gimbalsim;
using contract::Channels;

std::string env(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

const std::string& url() {
  static const std::string u = env("GIMBALSIM_BENCH_LCM_URL", "udpm://239.255.76.67:7697?ttl=0");
  return u;
}

const Channels& channels() {
  static const Channels ch = Channels::withPrefix("BENCH_");
  return ch;
}

void BM_ClockRead(benchmark::State& bs) {
  const clockid_t id = bs.range(0) == 0 ? CLOCK_MONOTONIC : CLOCK_THREAD_CPUTIME_ID;
  timespec ts{};
  for (auto _ : bs) {
    clock_gettime(id, &ts);
    benchmark::DoNotOptimize(ts);
  }
  bs.SetLabel(bs.range(0) == 0 ? "monotonic" : "thread_cpu");
}
BENCHMARK(BM_ClockRead)->Arg(0)->Arg(1);

// A message of each kind with the field sizes the bench sends (every array full).
template <class T>
T message() {
  T m{};
  if constexpr (std::is_same_v<T, gimbal_status_t>) m.seq = 1;
  return m;
}

template <class T>
void BM_Encode(benchmark::State& bs) {
  T m = message<T>();
  unsigned char buf[2048];
  benchmark::DoNotOptimize(buf);  // the buffer escapes: its bytes are kept, as a send reads them
  for (auto _ : bs) {
    benchmark::DoNotOptimize(m);  // the message may have changed: encoded again, not hoisted
    benchmark::DoNotOptimize(m.encode(buf, 0, sizeof buf));
    benchmark::ClobberMemory();
  }
}
BENCHMARK_TEMPLATE(BM_Encode, gimbal_status_t);
BENCHMARK_TEMPLATE(BM_Encode, gimbal_attitude_t);
BENCHMARK_TEMPLATE(BM_Encode, gimbal_truth_t);
BENCHMARK_TEMPLATE(BM_Encode, gimbal_command_t);

/// A receiving socket on the bench's port, as a peer process has one.
std::unique_ptr<lcm_wire::UdpmReceiver> peer(std::vector<std::string> channels_passed) {
  lcm_wire::ReassemblyLimits lim;
  auto rx = std::make_unique<lcm_wire::UdpmReceiver>(lim, lcm_wire::ChannelFilter(std::move(channels_passed)));
  if (std::string why; !rx->open(url(), 1 << 20, &why)) throw std::runtime_error("cannot open " + url() + ": " + why);
  return rx;
}

template <class T>
const std::string& channelOf() {
  const Channels& ch = channels();
  if constexpr (std::is_same_v<T, gimbal_status_t>) return ch.status;
  if constexpr (std::is_same_v<T, gimbal_attitude_t>) return ch.attitude;
  if constexpr (std::is_same_v<T, gimbal_truth_t>) return ch.truth;
  return ch.command;
}

/// The sender firmware_sim has, or null with the benchmark skipped.
std::unique_ptr<lcm_wire::UdpmSender> sender(benchmark::State& bs) {
  auto tx = std::make_unique<lcm_wire::UdpmSender>();
  if (std::string why; !tx->open(url(), &why)) {
    bench::fail(bs, "cannot send on " + url() + ": " + why, program::kNetwork);
    return nullptr;
  }
  return tx;
}

/// The receiving sockets of a bench on the port: /1 the plant's own, /2 and a controller's.
std::vector<std::unique_ptr<lcm_wire::UdpmReceiver>> peers(std::int64_t n) {
  std::vector<std::unique_ptr<lcm_wire::UdpmReceiver>> p;
  if (n >= 1) p.push_back(peer({channels().command}));
  if (n >= 2) p.push_back(peer({channels().status, channels().attitude}));
  return p;
}

/// What a peer let through is read, off the clock, so its buffer never fills.
void drainPeers(benchmark::State& bs, std::vector<std::unique_ptr<lcm_wire::UdpmReceiver>>& ps) {
  bs.PauseTiming();
  for (auto& p : ps) p->drain([](const lcm_wire::Message&, std::int64_t) {}, 1024);
  bs.ResumeTiming();
}

template <class T>
void BM_Publish(benchmark::State& bs) {
  const auto tx = sender(bs);
  if (!tx) return;
  auto ps = peers(bs.range(0));
  const T m = message<T>();
  const std::string& channel = channelOf<T>();
  long long sent = 0;
  for (auto _ : bs) {
    if (!tx->send(channel, m)) {
      bench::fail(bs, "publish failed", program::kNetwork);
      break;
    }
    if (++sent % 512 == 0) drainPeers(bs, ps);
  }
}
BENCHMARK_TEMPLATE(BM_Publish, gimbal_status_t)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(BM_Publish, gimbal_attitude_t)->Arg(2);
BENCHMARK_TEMPLATE(BM_Publish, gimbal_truth_t)->Arg(2);

void BM_PublishTick(benchmark::State& bs) {
  const auto tx = sender(bs);
  if (!tx) return;
  auto ps = peers(bs.range(0));
  const auto a = message<gimbal_attitude_t>();
  const auto s = message<gimbal_status_t>();
  const auto t = message<gimbal_truth_t>();
  long long ticks = 0;
  for (auto _ : bs) {
    tx->stageMessage(channels().attitude, a);
    tx->stageMessage(channels().status, s);
    tx->stageMessage(channels().truth, t);
    if (tx->flush() != 0) {
      bench::fail(bs, "publish failed", program::kNetwork);
      break;
    }
    if (++ticks % 256 == 0) drainPeers(bs, ps);
  }
}
BENCHMARK(BM_PublishTick)->Arg(2);

void BM_ReceiveCommand(benchmark::State& bs) {
  const auto tx = sender(bs);
  if (!tx) return;
  auto rx = peer({channels().command});
  const gimbal_command_t c = message<gimbal_command_t>();
  long long got = 0;
  for (auto _ : bs) {
    tx->send(channels().command, c);
    if (rx->waitDrain(100, 0, [&got](const lcm_wire::Message&, std::int64_t) { ++got; }, 16) <= 0) {
      bench::fail(bs, "the command did not come back within 100 ms", program::kNetwork);
      break;
    }
  }
  bs.counters["messages"] = static_cast<double>(got);
}
BENCHMARK(BM_ReceiveCommand);

/// The tick of a shipped scene as firmware_sim's lockstep loop builds it
/// (no profile: the target is the boresight at t = 0).
struct Tick {
  const firmware::PlantScene& ps;  // loaded once, by main's prepare (scene_once.hpp)
  firmware::Config c;
  explicit Tick(const std::string& scene)
      : ps(bench::plantSceneOnce(env("GIMBALSIM_SCENE_DIR", GIMBALSIM_SCENE_DIR) + "/" + scene + ".yaml", {})) {}
};

template <class F>
void withTick(benchmark::State& bs, const std::string& scene, F&& body) {
  const Tick t(scene);  // a scene that does not load refuses the run (exit 2), as gimbalsim_bench's do
  try {
    dispatchVariant(t.ps.scene.model, [&](auto tag) {
      using V = decltype(tag);
      auto tick = std::make_unique<firmware::BenchTick<V>>(t.ps, t.c, nullptr, nullptr);
      body(*tick);
    });
  } catch (const std::exception& e) {
    bench::fail(bs, e.what(), program::kInternal);
  }
  bs.SetLabel(scene);
}

const char* const kScenes[] = {"paper_ideal", "paper_clearance"};

void BM_Tick(benchmark::State& bs) {
  const bool truth = bs.range(1) != 0;
  withTick(bs, kScenes[bs.range(0)], [&](auto& tick) {
    std::int64_t k = 0;
    for (auto _ : bs) {  // no pause between the two: pausing reads clocks that cost as much as a part here
      benchmark::DoNotOptimize(tick.sample(k, k * 1000, truth));
      tick.advance();
      ++k;
    }
  });
}
BENCHMARK(BM_Tick)->ArgsProduct({{0, 1}, {0, 1}})->ArgNames({"scene", "truth"});

}  // namespace

int main(int argc, char** argv) {
  // the scenes of the BM_Tick runs the filter selects load before any part runs
  return gimbalsim::bench::benchmarkMain("gimbalsim_bench_tick", argc, argv, [](int n, char** v) {
    // (pass 121) a malformed URL is a bad argument (2), as every program's --lcm-url, not a row of errors (5)
    if (const char* given = std::getenv("GIMBALSIM_BENCH_LCM_URL"); given != nullptr) {
      const std::string why = *given ? gimbalsim::lcm_wire::lcmUrlProblem(given) : "set to nothing";
      if (!why.empty()) throw gimbalsim::InputError("GIMBALSIM_BENCH_LCM_URL '" + std::string(given) + "': " + why);
    }
    for (int scene = 0; scene < 2; ++scene) {
      for (int truth = 0; truth < 2; ++truth) {
        const std::string run = "BM_Tick/scene:" + std::to_string(scene) + "/truth:" + std::to_string(truth);
        if (gimbalsim::bench::filterSelects(n, v, run)) (void)Tick(kScenes[scene]);
      }
    }
  });
}
