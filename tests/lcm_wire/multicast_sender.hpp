// Raw UDP datagrams to a udpm URL's group and port, bypassing LCM (TTL 0,
// looped back to this host): the HIL attacker's malformed traffic and the
// interop test's non-LCM datagram.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <vector>

#include "gimbalsim/lcm_wire/udpm_receiver.hpp"

namespace gimbalsim::lcm_wire {

struct MulticastSender {
  std::vector<int> fds;
  sockaddr_in group{};
  long long sent = 0, failed = 0;

  MulticastSender() = default;
  MulticastSender(const MulticastSender&) = delete;
  MulticastSender& operator=(const MulticastSender&) = delete;
  ~MulticastSender() {
    for (const int fd : fds) ::close(fd);
  }

  /// `sockets` sending sockets (several: the kernel sees several sources).
  bool open(const LcmUrl& u, int sockets = 1) {
    group.sin_family = AF_INET;
    group.sin_addr.s_addr = u.group;
    group.sin_port = htons(u.port);
    for (int i = 0; i < sockets; ++i) {
      const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
      if (fd < 0) return false;
      const int ttl = 0, loop = 1;
      setsockopt(fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
      setsockopt(fd, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop);
      fds.push_back(fd);
    }
    return true;
  }

  /// Sends `size` bytes from socket number `socket` (modulo their count);
  /// true when the whole datagram went out.
  bool send(const void* data, std::size_t size, int socket = 0) {
    const int fd = fds[static_cast<std::size_t>(socket) % fds.size()];
    const bool ok = ::sendto(fd, data, size, 0, reinterpret_cast<const sockaddr*>(&group), sizeof group) ==
                    static_cast<ssize_t>(size);
    ++(ok ? sent : failed);
    return ok;
  }
  bool send(const std::vector<std::uint8_t>& bytes, int socket = 0) { return send(bytes.data(), bytes.size(), socket); }
};

}  // namespace gimbalsim::lcm_wire
