// hil_attack: test helper that attacks a bench on its udpm group with raw
// datagrams from its own sockets (never through liblcm, which cannot send
// malformed ones), in step with the plant's statuses and for a wall time:
//   --flood-pps N      fragment flood, N datagrams per second: fragment 0s
//                      on the command channel declaring 4 kB messages that
//                      never complete (from 8 source ports, so every
//                      reassembly buffer is taken and evicted), orphan
//                      fragments, fragments of unsubscribed channels, and
//                      fragments declaring 4 GB;
//   --malformed-every-ms T  every T ms of wall time once the plant has accepted
//                      a command, one datagram of each malformed kind: an LC03 shorter
//                      than its header (what crashes LCM 1.3.1), LC02/LC03
//                      with unterminated or 64-byte channel names, fragment_no
//                      >= count, count 0, data beyond the declared size, a bad magic;
//   --spoof-every-ms T every T ms once the plant has accepted a command (a
//                      status with last_command_seq >= 0), two well-formed commands on the
//                      command channel from this process (another source
//                      than the controller): seq INT64_MAX and the seq the
//                      controller will use next, both answering the newest
//                      status seen, with a large valid torque; and a spoofed
//                      status (seq and last_command_seq INT64_MAX) for the
//                      controller, which must ignore it (another source than its plant).
//   --spoof-at-once    spoof from the first status on, racing the controller
//                      for the plant's binding (a stranger that comes first).
// Time-driven, not status-driven: under its own flood on a loaded machine the
// attacker sees few statuses, and the attack must go on regardless.
// Runs --seconds of wall time, or until no status came for --idle-exit
// seconds after the first; prints what it sent. Exit 0, 2 bad arguments, 4 no socket.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "lcm_wire/lcm_datagrams.hpp"
#include "lcm_wire/multicast_sender.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"

namespace {

namespace bio = gimbalsim::lcm_wire;
using bio::datagrams::Bytes;

/// An LC03 fragment carrying `data` bytes of filler.
Bytes fragment(std::uint32_t seq, std::uint32_t size, std::uint32_t off, std::uint16_t no, std::uint16_t count,
               const std::string& ch, std::size_t data) {
  return bio::datagrams::fragment(seq, size, off, no, count, ch, Bytes(data, 0xAB));
}
Bytes shortMsg(const std::string& ch, const std::uint8_t* data, std::size_t n, bool terminate = true) {
  return bio::datagrams::shortMessage(ch, Bytes(data, data + n), 1, terminate);
}

}  // namespace

int main(int argc, char** argv) {
  std::string url, prefix;
  double seconds = 5.0, flood_pps = 0.0, idle_exit = 0.0;
  double malformed_ms = 0.0, spoof_ms = 0.0;
  bool spoof_at_once = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--lcm-url" && has) url = argv[++i];
    else if (a == "--channel-prefix" && has) prefix = argv[++i];
    else if (a == "--seconds" && has) seconds = std::atof(argv[++i]);
    else if (a == "--flood-pps" && has) flood_pps = std::atof(argv[++i]);
    else if (a == "--idle-exit" && has) idle_exit = std::atof(argv[++i]);
    else if (a == "--malformed-every-ms" && has) malformed_ms = std::atof(argv[++i]);
    else if (a == "--spoof-every-ms" && has) spoof_ms = std::atof(argv[++i]);
    else if (a == "--spoof-at-once") spoof_at_once = true;
    else {
      std::fprintf(stderr, "hil_attack: bad argument '%s'\n", a.c_str());
      return 2;
    }
  }
  std::string why;
  const bio::LcmUrl u = bio::parseLcmUrl(url, &why);
  if (u.kind != bio::LcmUrl::Kind::Udpm || !gimbalsim::contract::Channels::validPrefix(prefix)) {
    std::fprintf(stderr, "hil_attack: need a udpm URL and a valid prefix: %s\n", why.c_str());
    return 2;
  }
  const gimbalsim::contract::Channels ch = gimbalsim::contract::Channels::withPrefix(prefix);
  bio::MulticastSender tx;
  bio::UdpmReceiver rx(bio::ReassemblyLimits{}, bio::ChannelFilter({ch.status}));
  if (!tx.open(u, 8) || !rx.open(url, 1 << 20, &why)) {
    std::fprintf(stderr, "hil_attack: no socket: %s\n", why.c_str());
    return 4;
  }

  // The flood's datagrams, cycled.
  std::vector<Bytes> flood;
  for (std::uint16_t i = 0; i < 4; ++i) flood.push_back(fragment(1000 + i, 4096, 0, 0, 4, ch.command, 1000));
  flood.push_back(fragment(7, 4096, 2048, 2, 4, "", 1000));                     // orphan
  flood.push_back(fragment(8, 60000, 0, 0, 60, "SOMEONE_ELSES_CHANNEL", 1000));  // not subscribed
  flood.push_back(fragment(9, 0xFFFFFFFFu, 0, 0, 65535, ch.command, 1000));      // declares 4 GB
  // The malformed kinds.
  std::vector<Bytes> bad;
  bad.push_back(Bytes{0x4c, 0x43, 0x30, 0x33, 0, 0, 0, 1, 0, 0});               // LC03, 10 bytes
  bad.push_back(shortMsg(ch.command, nullptr, 0, false));                        // LC02, name not terminated
  bad.push_back(shortMsg(std::string(64, 'G'), nullptr, 0));                     // 64-byte channel
  Bytes unterminated = fragment(3, 100, 0, 0, 2, "", 0);
  unterminated.pop_back();  // drop the NUL: fragment 0's name runs to the end
  unterminated.insert(unterminated.end(), ch.command.begin(), ch.command.end());
  bad.push_back(unterminated);
  bad.push_back(fragment(4, 100, 0, 5, 2, "", 10));                              // fragment_no >= count
  bad.push_back(fragment(5, 100, 0, 0, 0, ch.command, 10));                      // count 0
  bad.push_back(fragment(6, 100, 0, 0, 2, ch.command, 200));                     // beyond the size
  bad.push_back(Bytes{'L', 'C', '0', '9', 1, 2, 3, 4, 5, 6, 7, 8});              // bad magic

  long long statuses = 0, spoofs = 0, malformed = 0, fake_statuses = 0;
  gimbalsim::gimbal_status_t st{};  // the newest status seen
  st.seq = -1;
  st.last_command_seq = -1;  // nothing accepted yet
  using Clock = std::chrono::steady_clock;
  Clock::time_point last_status = Clock::now();
  auto onStatus = [&](const bio::Message& m, std::int64_t) {
    gimbalsim::gimbal_status_t s{};
    if (s.decode(m.data, 0, static_cast<int>(m.size)) < 0) return;
    if (s.seq == std::numeric_limits<std::int64_t>::max()) return;  // our own spoofed status
    last_status = Clock::now();
    if (s.seq <= st.seq) return;
    st = s;
    ++statuses;
  };
  auto sendMalformed = [&] {
    for (const Bytes& b : bad) tx.send(b, static_cast<int>(malformed++ % 8));
  };
  auto sendSpoofs = [&] {
    constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
    for (std::int64_t seq : {kMax, st.last_command_seq < kMax ? st.last_command_seq + 1 : kMax}) {
        gimbalsim::gimbal_command_t c{};
        c.utime = st.utime;
        c.seq = seq;
        c.status_seq = st.seq;
        c.mode = gimbalsim::gimbal_command_t::MODE_TORQUE;
        c.torque[0] = 20.0;  // within the sanity range, far from what the controller sends
        c.torque[1] = -20.0;
        std::uint8_t buf[256];
        const int n = c.encode(buf, 0, sizeof buf);
        tx.send(shortMsg(ch.command, buf, static_cast<std::size_t>(n)), 7);
        ++spoofs;
    }
    gimbalsim::gimbal_status_t fake = st;
    fake.seq = std::numeric_limits<std::int64_t>::max();
    fake.last_command_seq = std::numeric_limits<std::int64_t>::max();
    fake.angle[0] = 1.0;
    std::uint8_t buf[512];
    const int n = fake.encode(buf, 0, sizeof buf);
    tx.send(shortMsg(ch.status, buf, static_cast<std::size_t>(n)), 6);
    ++fake_statuses;
  };

  const Clock::time_point t0 = Clock::now();
  Clock::time_point next_bad = t0, next_spoof = t0;
  auto every = [](double ms) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms)); };
  const auto end = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  long long flooded = 0, scheduled = 0;
  std::size_t next = 0;
  while (Clock::now() < end) {
    if (idle_exit > 0.0 && statuses > 0 && Clock::now() - last_status > std::chrono::duration<double>(idle_exit)) break;
    rx.drain(onStatus, 1024);
    // The plant has bound the controller once a status says it accepted a
    // command (a status 1 sent before the answer to status 0 arrived does not:
    // a spoof then could win the binding, which --spoof-at-once does on purpose).
    const bool bound = st.last_command_seq >= 0;
    if (bound && malformed_ms > 0.0 && Clock::now() >= next_bad) {
      sendMalformed();
      next_bad = Clock::now() + every(malformed_ms);
    }
    if ((bound || (spoof_at_once && st.seq >= 0)) && spoof_ms > 0.0 && Clock::now() >= next_spoof) {
      sendSpoofs();
      next_spoof = Clock::now() + every(spoof_ms);
    }
    // Keep to the flood schedule in bursts of at most 500, so the timers
    // above keep running; debt beyond 0.1 s is given up (the machine cannot
    // send that fast: the printed rate says what was sent).
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    const auto due = static_cast<long long>(elapsed * flood_pps);
    scheduled = std::max(scheduled, due - static_cast<long long>(0.1 * flood_pps));
    for (int burst = 0; scheduled < due && burst < 500; ++burst, ++scheduled, ++flooded) {
      const Bytes& b = flood[next % flood.size()];
      tx.send(b, static_cast<int>(next % 8));
      ++next;
    }
    if (scheduled >= due) rx.wait(1);  // ahead of the schedule: wait for statuses
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("hil_attack: %.2f s: flood %lld datagrams (%.0f per s), %lld malformed, %lld spoofed commands, "
              "%lld spoofed statuses, %lld statuses seen, %lld send failures\n",
              wall, flooded, static_cast<double>(flooded) / wall, malformed, spoofs, fake_statuses, statuses, tx.failed);
  return 0;
}
