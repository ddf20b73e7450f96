// Every field of every message type survives encode/decode; decoding (and
// encoding into a preallocated buffer) makes no heap allocation; bytes of the
// wrong type or truncated bytes are refused by decode.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "counting_new.hpp"
#include "gimbalsim/channels.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_loop_stats_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"

namespace gimbalsim {
namespace {

// Field lists, one per type: f(a.field, b.field) for every field. The test
// FieldListCoversTheEncoding checks each list against the encoded size, so a
// field added to a .lcm file and forgotten here fails the test.
template <class F>
void fields(gimbal_command_t& a, gimbal_command_t& b, F&& f) {
  f(a.utime, b.utime); f(a.seq, b.seq); f(a.status_seq, b.status_seq);
  f(a.mode, b.mode); f(a.torque, b.torque);
}
template <class F>
void fields(gimbal_status_t& a, gimbal_status_t& b, F&& f) {
  f(a.utime, b.utime); f(a.seq, b.seq); f(a.angle, b.angle); f(a.rate, b.rate);
  f(a.applied_torque, b.applied_torque); f(a.faults, b.faults);
  f(a.last_command_seq, b.last_command_seq); f(a.commands_received, b.commands_received);
  f(a.commands_rejected, b.commands_rejected); f(a.commands_missed, b.commands_missed);
}
template <class F>
void fields(gimbal_truth_t& a, gimbal_truth_t& b, F&& f) {
  f(a.utime, b.utime); f(a.seq, b.seq); f(a.sim_time, b.sim_time); f(a.base_position, b.base_position);
  f(a.base_quaternion, b.base_quaternion); f(a.base_rate, b.base_rate);
  f(a.base_velocity, b.base_velocity); f(a.joint_angle, b.joint_angle);
  f(a.joint_rate, b.joint_rate); f(a.applied_torque, b.applied_torque);
  f(a.eccentricity, b.eccentricity); f(a.penetration, b.penetration);
  f(a.contact_normal_force, b.contact_normal_force);
  f(a.contact_tangential_force, b.contact_tangential_force);
  f(a.joint2_force, b.joint2_force); f(a.boresight, b.boresight);
  f(a.target_boresight, b.target_boresight); f(a.pointing_error, b.pointing_error);
  f(a.momentum_linear, b.momentum_linear); f(a.momentum_angular, b.momentum_angular);
  f(a.energy, b.energy); f(a.faults, b.faults);
}
template <class F>
void fields(gimbal_loop_stats_t& a, gimbal_loop_stats_t& b, F&& f) {
  f(a.utime, b.utime); f(a.ticks, b.ticks);
  f(a.period_p50, b.period_p50); f(a.period_p99, b.period_p99);
  f(a.period_p999, b.period_p999); f(a.period_max, b.period_max);
  f(a.lateness_p50, b.lateness_p50); f(a.lateness_p99, b.lateness_p99);
  f(a.lateness_p999, b.lateness_p999); f(a.lateness_max, b.lateness_max);
  f(a.compute_p50, b.compute_p50); f(a.compute_p99, b.compute_p99);
  f(a.compute_max, b.compute_max); f(a.overruns, b.overruns);
  f(a.roundtrip_p50, b.roundtrip_p50); f(a.roundtrip_p99, b.roundtrip_p99);
  f(a.roundtrip_p999, b.roundtrip_p999); f(a.roundtrip_max, b.roundtrip_max);
  f(a.substeps_mean, b.substeps_mean); f(a.substeps_max, b.substeps_max);
  f(a.commands_received, b.commands_received); f(a.commands_rejected, b.commands_rejected);
  f(a.commands_missed, b.commands_missed); f(a.realtime, b.realtime); f(a.lockstep, b.lockstep);
}

// A distinct, non-trivial value for element k: uses high bits of 64-bit
// integers, negative numbers and doubles with full mantissas, so a field
// truncated, byte-swapped or swapped with its neighbour shows.
struct Filler {
  int k = 0;
  int next() { return ++k; }
  double sign() const { return k % 2 ? -1.0 : 1.0; }
  void set(std::int64_t& x) { const int i = next(); x = static_cast<std::int64_t>(sign()) * ((std::int64_t{0x1234567} << 28) + 7919LL * i); }
  void set(std::int32_t& x) { const int i = next(); x = static_cast<std::int32_t>(sign()) * (0x123456 + 31 * i); }
  void set(std::int8_t& x) { const int i = next(); x = static_cast<std::int8_t>(-100 + (13 * i) % 200); }
  void set(double& x) { const int i = next(); x = sign() * std::sqrt(2.0 + i) * std::exp(0.37 * i); }
  template <class T, std::size_t N>
  void set(T (&x)[N]) { for (auto& e : x) set(e); }
};

struct Bytes {
  std::size_t n = 0;
  template <class T> void add(const T&) { n += sizeof(T); }
  template <class T, std::size_t N> void add(const T (&)[N]) { n += N * sizeof(T); }
};

template <class T> bool same(const T& a, const T& b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }
template <class T, std::size_t N> bool same(const T (&a)[N], const T (&b)[N]) {
  for (std::size_t i = 0; i < N; ++i) if (!same(a[i], b[i])) return false;
  return true;
}

template <class M>
M filled() {
  M a{}, unused{};
  Filler fill;
  fields(a, unused, [&](auto& x, auto&) { fill.set(x); });
  return a;
}

template <class M>
void checkRoundTrip() {
  M a = filled<M>();
  std::vector<std::uint8_t> buf(a.getEncodedSize());
  ASSERT_EQ(a.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  M b{};
  ASSERT_EQ(b.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  int i = 0;
  fields(a, b, [&](auto& x, auto& y) {
    EXPECT_TRUE(same(x, y)) << M::getTypeName() << ": field #" << i << " changed in the round trip";
    ++i;
  });
  // And the filler really set distinct values: no two scalar fields equal.
  M zero{};
  int changed = 0;
  fields(a, zero, [&](auto& x, auto& z) { changed += same(x, z) ? 0 : 1; });
  EXPECT_EQ(changed, i) << M::getTypeName() << ": some field was left at zero by the filler";
}

TEST(LcmTypes, EveryFieldSurvivesEncodeDecode) {
  checkRoundTrip<gimbal_command_t>();
  checkRoundTrip<gimbal_status_t>();
  checkRoundTrip<gimbal_truth_t>();
  checkRoundTrip<gimbal_loop_stats_t>();
}

template <class M>
void checkCoverage() {
  M a{}, b{};
  Bytes bytes;
  fields(a, b, [&](auto& x, auto&) { bytes.add(x); });
  // Encoded size = 8-byte fingerprint + the fields (all fixed-size, no padding on the wire).
  EXPECT_EQ(static_cast<int>(bytes.n) + 8, a.getEncodedSize())
      << M::getTypeName() << ": the test's field list does not cover the type";
}

TEST(LcmTypes, FieldListCoversTheEncoding) {
  checkCoverage<gimbal_command_t>();
  checkCoverage<gimbal_status_t>();
  checkCoverage<gimbal_truth_t>();
  checkCoverage<gimbal_loop_stats_t>();
}

template <class M>
long long allocationsOfDecodeAndEncode() {
  const M a = filled<M>();
  std::uint8_t buf[1024];
  const int n = a.getEncodedSize();
  EXPECT_LE(n, static_cast<int>(sizeof buf));
  M b{};
  EXPECT_EQ(a.encode(buf, 0, n), n);  // warm-up (the fingerprint is a function-local static)
  EXPECT_EQ(b.decode(buf, 0, n), n);
  const long long before = test::g_allocations.load();
  for (int k = 0; k < 100; ++k) {
    if (a.encode(buf, 0, n) != n || b.decode(buf, 0, n) != n) ADD_FAILURE() << "codec failed";
  }
  return test::g_allocations.load() - before;
}

TEST(LcmTypes, TheCounterSeesAllocations) {
  const long long before = test::g_allocations.load();
  std::vector<double>* volatile p = new std::vector<double>(100);
  delete p;
  EXPECT_GE(test::g_allocations.load() - before, 1);
}

TEST(LcmTypes, EncodeIntoBufferAndDecodeAllocateNothing) {
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_command_t>(), 0);
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_status_t>(), 0);
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_truth_t>(), 0);
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_loop_stats_t>(), 0);
}

TEST(LcmTypes, WrongTypeAndTruncatedBytesAreRefused) {
  const gimbal_status_t st = filled<gimbal_status_t>();
  std::vector<std::uint8_t> buf(st.getEncodedSize());
  st.encode(buf.data(), 0, static_cast<int>(buf.size()));
  gimbal_command_t cmd{};
  EXPECT_LT(cmd.decode(buf.data(), 0, static_cast<int>(buf.size())), 0) << "fingerprint mismatch must fail";

  const gimbal_command_t good = filled<gimbal_command_t>();
  std::vector<std::uint8_t> cbuf(good.getEncodedSize());
  good.encode(cbuf.data(), 0, static_cast<int>(cbuf.size()));
  EXPECT_LT(cmd.decode(cbuf.data(), 0, static_cast<int>(cbuf.size()) - 1), 0) << "truncated must fail";
  EXPECT_EQ(cmd.decode(cbuf.data(), 0, static_cast<int>(cbuf.size())), static_cast<int>(cbuf.size()));
}

TEST(Channels, PrefixAndNames) {
  const Channels plain;
  EXPECT_EQ(plain.command, "GIMBAL_COMMAND");
  EXPECT_EQ(plain.status, "GIMBAL_STATUS");
  EXPECT_EQ(plain.truth, "GIMBAL_TRUTH");
  EXPECT_EQ(plain.loop_stats, "GIMBAL_LOOP_STATS");
  const Channels b2 = Channels::withPrefix("BENCH2_");
  EXPECT_EQ(b2.command, "BENCH2_GIMBAL_COMMAND");
  EXPECT_EQ(b2.loop_stats, "BENCH2_GIMBAL_LOOP_STATS");
  EXPECT_TRUE(Channels::validPrefix("BENCH2_"));
  EXPECT_TRUE(Channels::validPrefix(""));
  EXPECT_FALSE(Channels::validPrefix("bench-2"));
}

}  // namespace
}  // namespace gimbalsim
