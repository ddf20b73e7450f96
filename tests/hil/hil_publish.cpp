// hil_publish: test helper that puts bad messages on a bench's command channel
// with LCM's raw publish(channel, data, size), in step with the plant: it
// listens to <prefix>GIMBAL_STATUS and, on every status whose seq is
// `offset` mod `every`, publishes the next message of a fixed cycle of kinds
// (below), until `count` are out. Exit 0 when all were published, 1 on
// timeout, 2 on bad arguments, 4 if LCM cannot start.
//
//   hil_publish --lcm-url URL [--channel-prefix P] [--count N] [--every K] [--offset J] [--timeout S]
//
// Kinds, in order: random bytes; a gimbal_status_t (wrong type: fingerprint);
// a gimbal_command_t cut 5 bytes short; a gimbal_command_t with 3 trailing
// bytes; a gimbal_truth_t; a well-formed command with a NaN torque; a
// well-formed command with an unknown mode. The last two decode, so they are
// rejected by validation, not by the decoder.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"

namespace {

constexpr int kKinds = 7;

std::vector<unsigned char> message(int kind) {
  std::vector<unsigned char> b(4096);
  auto encode = [&b](const auto& m) {
    const int n = m.encode(b.data(), 0, static_cast<int>(b.size()));
    b.resize(static_cast<size_t>(n));
  };
  gimbalsim::gimbal_command_t cmd;
  cmd.utime = 0;
  cmd.seq = 1000000000;  // far ahead, so only the NaN / mode check can refuse it
  cmd.status_seq = 0;
  cmd.mode = gimbalsim::gimbal_command_t::MODE_TORQUE;
  cmd.torque[0] = 1.0;
  cmd.torque[1] = -1.0;
  switch (kind) {
    case 0: {  // random bytes (fixed seed)
      b.resize(64);
      unsigned x = 12345u;
      for (auto& c : b) c = static_cast<unsigned char>((x = x * 1103515245u + 12345u) >> 16);
      break;
    }
    case 1: {
      gimbalsim::gimbal_status_t s{};
      s.seq = 7;
      encode(s);
      break;
    }
    case 2:
      encode(cmd);
      b.resize(b.size() - 5);
      break;
    case 3:
      encode(cmd);
      b.push_back(1);
      b.push_back(2);
      b.push_back(3);
      break;
    case 4: {
      gimbalsim::gimbal_truth_t t{};
      encode(t);
      break;
    }
    case 5:
      cmd.torque[0] = std::nan("");
      encode(cmd);
      break;
    default:
      cmd.mode = 7;
      encode(cmd);
      break;
  }
  return b;
}

struct Publisher {
  lcm::LCM* lcm;
  std::string command_channel;
  long long every = 100, offset = 50, count = 14, sent = 0;

  void onStatus(const lcm::ReceiveBuffer* rb, const std::string&) {
    gimbalsim::gimbal_status_t s;
    if (s.decode(rb->data, 0, static_cast<int>(rb->data_size)) < 0) return;
    if (sent >= count || s.seq % every != offset || s.seq < last_seq_ + 1) return;
    last_seq_ = s.seq;  // once per status (lockstep re-publishes status 0 only)
    const std::vector<unsigned char> m = message(static_cast<int>(sent % kKinds));
    if (lcm->publish(command_channel, m.data(), static_cast<unsigned>(m.size())) == 0) ++sent;
  }

 private:
  long long last_seq_ = -1;
};

}  // namespace

int main(int argc, char** argv) {
  std::string url, prefix;
  Publisher p;
  double timeout_s = 30.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--lcm-url" && has) url = argv[++i];
    else if (a == "--channel-prefix" && has) prefix = argv[++i];
    else if (a == "--count" && has) p.count = std::atoll(argv[++i]);
    else if (a == "--every" && has) p.every = std::atoll(argv[++i]);
    else if (a == "--offset" && has) p.offset = std::atoll(argv[++i]);
    else if (a == "--timeout" && has) timeout_s = std::atof(argv[++i]);
    else {
      std::fprintf(stderr, "hil_publish: bad argument '%s'\n", a.c_str());
      return 2;
    }
  }
  if (p.every < 1 || p.count < 0 || !gimbalsim::contract::Channels::validPrefix(prefix)) {
    std::fprintf(stderr, "hil_publish: bad --every, --count or --channel-prefix\n");
    return 2;
  }
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "hil_publish: LCM could not start with '%s'\n", url.c_str());
    return 4;
  }
  const gimbalsim::contract::Channels ch = gimbalsim::contract::Channels::withPrefix(prefix);
  p.lcm = &lcm;
  p.command_channel = ch.command;
  lcm.subscribe(ch.status, &Publisher::onStatus, &p);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (p.sent < p.count && std::chrono::steady_clock::now() < end) lcm.handleTimeout(100);
  std::printf("hil_publish: published %lld of %lld bad messages on %s\n", p.sent, p.count, ch.command.c_str());
  return p.sent == p.count ? 0 : 1;
}
