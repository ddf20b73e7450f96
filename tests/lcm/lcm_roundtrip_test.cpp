// Every field of every message type survives encode/decode; decoding (and
// encoding into a preallocated buffer) makes no heap allocation; bytes of the
// wrong type or truncated bytes are refused by decode. firmware_sim's field
// lists (messages.hpp) cover the messages and its LCM-free structs, so a
// message copied through them writes the same CSV row as the struct.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "alloc_guard.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/firmware_sim/csv_rows.hpp"
#include "gimbalsim/gimbal_antenna_t.hpp"
#include "gimbalsim/gimbal_attitude_t.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_loop_stats_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"

namespace gimbalsim {
using namespace contract;  // NOLINT: the message contract under test
namespace {

// The field lists are firmware_sim's own (messages.hpp), the ones its LCM
// bridge and CSV writers use: f(a.field, b.field) for every field. The test
// FieldListCoversTheEncoding checks each list against the encoded size, so a
// field added to a .lcm file and forgotten in the list fails the test.
template <class M> struct ListOf;
template <> struct ListOf<gimbal_command_t> { using type = contract::CommandFields; };
template <> struct ListOf<gimbal_status_t> { using type = contract::StatusFields; };
template <> struct ListOf<gimbal_truth_t> { using type = contract::TruthFields; };
template <> struct ListOf<gimbal_loop_stats_t> { using type = contract::LoopStatsFields; };
template <> struct ListOf<gimbal_attitude_t> { using type = contract::AttitudeFields; };
template <> struct ListOf<gimbal_antenna_t> { using type = contract::AntennaFields; };

template <class M, class F>
void fields(M& a, M& b, F&& f) {
  ListOf<M>::type::visit([&](contract::Columns, auto& x, auto& y) { f(x, y); }, a, b);
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
  checkRoundTrip<gimbal_attitude_t>();
  checkRoundTrip<gimbal_antenna_t>();
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
  checkCoverage<gimbal_attitude_t>();
  checkCoverage<gimbal_antenna_t>();
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
  EXPECT_GE(test::probeAllocations(), 1);
}

TEST(LcmTypes, EncodeIntoBufferAndDecodeAllocateNothing) {
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_command_t>(), 0);
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_status_t>(), 0);
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_truth_t>(), 0);
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_loop_stats_t>(), 0);
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_attitude_t>(), 0);
  EXPECT_EQ(allocationsOfDecodeAndEncode<gimbal_antenna_t>(), 0);
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

// Each field list visits every member of firmware_sim's LCM-free struct in
// declaration order: each field starts where the previous one ended (up to
// alignment), and the last one ends the struct (up to its alignment).
template <class D, class S>
void checkStructCoverage(const char* name) {
  S s{};
  const auto* base = reinterpret_cast<const unsigned char*>(&s);
  std::size_t end = 0;
  int i = 0;
  D::visit(
      [&](contract::Columns, const auto& x) {
        const std::size_t at = static_cast<std::size_t>(reinterpret_cast<const unsigned char*>(&x) - base);
        const std::size_t align = alignof(std::remove_all_extents_t<std::remove_reference_t<decltype(x)>>);
        EXPECT_EQ(at, (end + align - 1) / align * align) << name << ": field #" << i << " is not the next member";
        end = at + sizeof(x);
        ++i;
      },
      s);
  EXPECT_EQ((end + alignof(S) - 1) / alignof(S) * alignof(S), sizeof(S)) << name << ": members after the last field";
}

TEST(FirmwareMessages, FieldListsCoverTheFirmwareStructs) {
  checkStructCoverage<contract::CommandFields, contract::Command>("Command");
  checkStructCoverage<contract::StatusFields, contract::Status>("Status");
  checkStructCoverage<contract::TruthFields, contract::Truth>("Truth");
  checkStructCoverage<contract::AttitudeFields, contract::Attitude>("Attitude");
  checkStructCoverage<contract::AntennaFields, contract::Antenna>("Antenna");
}

template <class D, class S, class M>
void checkStructToMessage() {
  M filled_msg = filled<M>();
  S s{};
  contract::copyFields<D>(s, filled_msg);  // message -> struct (as a decoded command)
  M m{};
  contract::copyFields<D>(m, s);  // struct -> message (as status and truth)
  fields(m, filled_msg, [&](auto& x, auto& y) { EXPECT_TRUE(same(x, y)) << M::getTypeName(); });
  // One CSV row for the struct and the message, and as many header cells as values.
  char* a = nullptr;
  char* b = nullptr;
  std::size_t na = 0, nb = 0;
  std::FILE* fa = open_memstream(&a, &na);
  std::FILE* fb = open_memstream(&b, &nb);
  firmware::csv::writeRow<D>(fa, s);
  firmware::csv::writeRow<D>(fb, m);
  std::fclose(fa);
  std::fclose(fb);
  const std::string row_s(a, na), row_m(b, nb), header = firmware::csv::header<D>();
  std::free(a);
  std::free(b);
  EXPECT_EQ(row_s, row_m) << M::getTypeName();
  EXPECT_EQ(std::count(row_s.begin(), row_s.end(), ','), std::count(header.begin(), header.end(), ','))
      << M::getTypeName() << ": " << header;
}

TEST(FirmwareMessages, StructAndMessageCarryTheSameValuesAndRows) {
  checkStructToMessage<contract::CommandFields, contract::Command, gimbal_command_t>();
  checkStructToMessage<contract::StatusFields, contract::Status, gimbal_status_t>();
  checkStructToMessage<contract::TruthFields, contract::Truth, gimbal_truth_t>();
  checkStructToMessage<contract::AttitudeFields, contract::Attitude, gimbal_attitude_t>();
  checkStructToMessage<contract::AntennaFields, contract::Antenna, gimbal_antenna_t>();
}

TEST(Channels, PrefixAndNames) {
  const Channels plain;
  EXPECT_EQ(plain.command, "GIMBAL_COMMAND");
  EXPECT_EQ(plain.status, "GIMBAL_STATUS");
  EXPECT_EQ(plain.truth, "GIMBAL_TRUTH");
  EXPECT_EQ(plain.loop_stats, "GIMBAL_LOOP_STATS");
  EXPECT_EQ(plain.attitude, "GIMBAL_ATTITUDE");
  const Channels b2 = Channels::withPrefix("BENCH2_");
  EXPECT_EQ(b2.command, "BENCH2_GIMBAL_COMMAND");
  EXPECT_EQ(b2.loop_stats, "BENCH2_GIMBAL_LOOP_STATS");
  EXPECT_EQ(b2.attitude, "BENCH2_GIMBAL_ATTITUDE");
  EXPECT_TRUE(Channels::validPrefix("BENCH2_"));
  EXPECT_TRUE(Channels::validPrefix(""));
  EXPECT_FALSE(Channels::validPrefix("bench-2"));
  // every name within LCM's 63 characters (pass 66: a 50-character prefix lost every command)
  EXPECT_TRUE(Channels::validPrefix(std::string(46, 'A')));
  const Channels longest = Channels::withPrefix(std::string(46, 'A'));
  EXPECT_EQ(longest.loop_stats.size(), Channels::kMaxChannelName);
  for (const std::string& name : {longest.command, longest.status, longest.truth, longest.attitude, longest.antenna}) {
    EXPECT_LE(name.size(), Channels::kMaxChannelName) << name;
  }
  EXPECT_EQ(Channels::prefixProblem(std::string(47, 'A')),
            "at most 46 characters: LCM names no channel longer than 63 (GIMBAL_LOOP_STATS would have 64)");
}

}  // namespace
}  // namespace gimbalsim
