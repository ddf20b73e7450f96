#include "gimbalsim/lcm_wire/udpm_sender.hpp"

#include <arpa/inet.h>
#include <unistd.h>

#include <cerrno>

namespace gimbalsim::lcm_wire {

UdpmSender::~UdpmSender() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpmSender::open(const std::string& url, std::string* why) {
  const LcmUrl u = parseLcmUrl(url, why);
  if (u.kind == LcmUrl::Kind::InProcess) {
    in_process_ = true;
    return true;
  }
  if (u.kind != LcmUrl::Kind::Udpm) return false;
  auto fail = [&](const char* step) { return socketStepFailed(u, step, &fd_, why); };
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) return fail("socket");
  const int ttl = u.ttl, loop = 1;  // as liblcm: the URL's TTL, and this host's own listeners hear it
  if (setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) < 0) return fail("IP_MULTICAST_TTL");
  if (setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) < 0) return fail("IP_MULTICAST_LOOP");
  to_.sin_family = AF_INET;
  to_.sin_addr.s_addr = u.group;
  to_.sin_port = htons(u.port);
  return true;
}

void UdpmSender::putHeader(Slot& s, std::string_view channel) noexcept {
  const std::uint32_t magic = htonl(kMagicShort), seq = htonl(seqno_++);
  std::memcpy(s.bytes.data(), &magic, 4);
  std::memcpy(s.bytes.data() + 4, &seq, 4);
  std::memcpy(s.bytes.data() + kShortHeaderBytes, channel.data(), channel.size());
  s.bytes[kShortHeaderBytes + channel.size()] = 0;
}

int UdpmSender::flush() noexcept {
  const int n = staged_;
  staged_ = 0;
  if (n == 0) return 0;
  if (fd_ < 0) {  // memq:// (nobody hears) or never opened (nothing can go out)
    if (in_process_) return 0;
    errors_ += n;
    return n;
  }
  iovec iov[kMaxBatch];
  mmsghdr hdr[kMaxBatch];
  for (int i = 0; i < n; ++i) {
    iov[i] = iovec{slots_[static_cast<std::size_t>(i)].bytes.data(), slots_[static_cast<std::size_t>(i)].size};
    hdr[i] = mmsghdr{};
    hdr[i].msg_hdr.msg_name = &to_;
    hdr[i].msg_hdr.msg_namelen = sizeof to_;
    hdr[i].msg_hdr.msg_iov = &iov[i];
    hdr[i].msg_hdr.msg_iovlen = 1;
  }
  int done = 0, failed = 0;
  while (done < n) {
    const int r = ::sendmmsg(fd_, hdr + done, static_cast<unsigned>(n - done), 0);
    if (r > 0) {
      done += r;
    } else if (r < 0 && errno == EINTR) {
      continue;
    } else {
      ++failed;  // this message cannot go out (sendmmsg reports the first failure): count it, go on
      ++done;
    }
  }
  sent_ += n - failed;
  errors_ += failed;
  return failed;
}

}  // namespace gimbalsim::lcm_wire
