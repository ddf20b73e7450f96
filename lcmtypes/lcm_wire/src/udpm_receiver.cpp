#include "gimbalsim/lcm_wire/udpm_receiver.hpp"

#include <arpa/inet.h>
#include <linux/filter.h>
#include <netinet/in.h>
#include <poll.h>
#include <sched.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace gimbalsim::lcm_wire {

std::int64_t monotonicNs() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1000000000 + ts.tv_nsec;
}

namespace {

// The kernel's socket filter (classic BPF, SO_ATTACH_FILTER): a UDP socket's
// program sees the datagram from its UDP header, so the LCM payload starts at
// byte 8 (magic), the LC02 channel name at byte 16 (after the sequence number).
constexpr std::uint32_t kUdpHeader = 8, kChannelAt = kUdpHeader + 8;
constexpr std::size_t kMaxFilterChannels = 16, kMaxFilterName = 255;

sock_filter stmt(std::uint16_t code, std::uint32_t k) { return sock_filter{code, 0, 0, k}; }
sock_filter jeq(std::uint32_t k, std::uint8_t jf) { return sock_filter{BPF_JMP | BPF_JEQ | BPF_K, 0, jf, k}; }

/// The program: a datagram that is not LC02 passes; an LC02 one passes when
/// its channel (NUL included) equals one of `names`, word by word; else it is
/// dropped. Empty when the names do not fit the instruction set's jumps.
std::vector<sock_filter> channelProgram(const std::vector<std::string>& names) {
  std::vector<sock_filter> p;
  if (names.empty() || names.size() > kMaxFilterChannels) return p;
  p.push_back(stmt(BPF_LD | BPF_W | BPF_ABS, kUdpHeader));
  p.push_back(sock_filter{BPF_JMP | BPF_JEQ | BPF_K, 1, 0, kMagicShort});
  p.push_back(stmt(BPF_RET | BPF_K, 0xFFFFFFFFu));  // not a whole LCM message: up to the reassembler
  for (const std::string& name : names) {
    if (name.size() > kMaxFilterName) return {};
    const std::string z = name + '\0';
    std::vector<sock_filter> block;  // compare z at kChannelAt; jf targets patched below
    for (std::size_t at = 0; at < z.size();) {
      const std::size_t len = z.size() - at >= 4 ? 4 : z.size() - at >= 2 ? 2 : 1;
      std::uint32_t v = 0;
      for (std::size_t i = 0; i < len; ++i) v = v << 8 | static_cast<std::uint8_t>(z[at + i]);
      const std::uint16_t size = len == 4 ? BPF_W : len == 2 ? BPF_H : BPF_B;
      block.push_back(stmt(BPF_LD | size | BPF_ABS, kChannelAt + static_cast<std::uint32_t>(at)));
      block.push_back(jeq(v, 0));
      at += len;
    }
    block.push_back(stmt(BPF_RET | BPF_K, 0xFFFFFFFFu));  // this channel: pass
    for (std::size_t i = 0; i < block.size(); ++i) {
      if (BPF_CLASS(block[i].code) == BPF_JMP) block[i].jf = static_cast<std::uint8_t>(block.size() - 1 - i);
    }
    p.insert(p.end(), block.begin(), block.end());
  }
  p.push_back(stmt(BPF_RET | BPF_K, 0));  // another channel's whole message: dropped
  return p;
}

std::int64_t realtimeUs() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1000000 + ts.tv_nsec / 1000;
}

bool parseInt(const std::string& s, long lo, long hi, long* out) {
  // A leading zero is refused: LCM's own parse reads "07815" as octal (port 7), so the
  // publisher and this receiver would each take a different number and never meet.
  if (s.empty() || s.size() > 10 || (s.size() > 1 && s[0] == '0')) return false;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  const long v = std::strtol(s.c_str(), nullptr, 10);
  if (v < lo || v > hi) return false;
  *out = v;
  return true;
}

}  // namespace

LcmUrl parseLcmUrl(const std::string& given, std::string* why) {
  LcmUrl u;
  u.text = given;
  if (u.text.empty()) {
    const char* env = std::getenv("LCM_DEFAULT_URL");
    u.text = env != nullptr && *env != '\0' ? env : "udpm://239.255.76.67:7667?ttl=0";
  }
  auto fail = [&](const std::string& w) {
    u.kind = LcmUrl::Kind::Unsupported;
    if (why) *why = "LCM URL '" + u.text + "': " + w;
    return u;
  };
  const std::size_t sep = u.text.find("://");
  if (sep == std::string::npos) return fail("expected provider://network?options");
  const std::string provider = u.text.substr(0, sep);
  const std::string rest = u.text.substr(sep + 3);
  if (provider == "memq") {
    u.kind = LcmUrl::Kind::InProcess;
    return u;
  }
  if (provider != "udpm") return fail("provider '" + provider + "' is not received here (udpm:// or memq://)");
  const std::size_t q = rest.find('?');
  const std::string net = rest.substr(0, q);
  const std::string opts = q == std::string::npos ? "" : rest.substr(q + 1);
  std::string addr = net, port = "7667";
  if (const std::size_t c = net.rfind(':'); c != std::string::npos) {
    addr = net.substr(0, c);
    port = net.substr(c + 1);
  }
  // No network at all ("udpm://") is LCM's default group and port; an empty group before a port
  // ("udpm://:7667") is refused below, as LCM's publisher fails on it ("Bad multicast IP address").
  if (net.empty()) addr = "239.255.76.67";
  in_addr a{};
  if (inet_pton(AF_INET, addr.c_str(), &a) != 1) return fail("'" + addr + "' is not an IPv4 address");
  if (!IN_MULTICAST(ntohl(a.s_addr))) return fail("'" + addr + "' is not a multicast group (224.0.0.0/4)");
  long p = 0;
  if (!parseInt(port, 1, 65535, &p)) {
    return fail("port '" + port + "' is not a whole number in 1..65535 written without a leading zero");
  }
  u.group = a.s_addr;
  u.port = static_cast<std::uint16_t>(p);
  // An empty option ('?', '&&', a '&' at an end) or one given twice ('ttl=1&ttl=0': which holds?) is
  // refused, as an empty list item of a flag is.
  if (q != std::string::npos && (opts.empty() || opts.front() == '&' || opts.back() == '&' ||
                                 opts.find("&&") != std::string::npos)) {
    return fail("an empty option (a '?' with none after it, two '&' in a row, or one at an end)");
  }
  std::stringstream ss(opts);
  std::vector<std::string> seen;
  for (std::string kv; std::getline(ss, kv, '&');) {
    const std::size_t e = kv.find('=');
    const std::string k = kv.substr(0, e), v = e == std::string::npos ? "" : kv.substr(e + 1);
    if (std::find(seen.begin(), seen.end(), k) != seen.end() && !k.empty()) {
      return fail("option '" + k + "' given twice");
    }
    seen.push_back(k);
    long n = 0;
    if (k == "recv_buf_size") {
      if (!parseInt(v, 1, 1L << 30, &n)) return fail("recv_buf_size '" + v + "' is not in 1..2^30");
      u.recv_buf_size = static_cast<int>(n);
    } else if (k == "ttl") {
      // LCM warns of a ttl it cannot read and keeps its own default: ttl=0 (the bench's "stay on this
      // host") mistyped would put the traffic on the network
      if (!(v == "0" || parseInt(v, 1, 255, &n))) return fail("ttl '" + v + "' is not a whole number in 0..255");
      u.ttl = static_cast<int>(n);  // "0" leaves n at 0
    } else if (k == "transmit_only") {
      if (v != "true" && v != "false") return fail("transmit_only '" + v + "' is not true or false");
    } else if (k.empty() && !kv.empty()) {  // "&=5": an option that names nothing
      return fail("an option without a name ('" + kv + "')");
    } else if (!k.empty()) {
      return fail("unknown option '" + k + "' (ttl, recv_buf_size, transmit_only)");
    }
  }
  u.kind = LcmUrl::Kind::Udpm;
  return u;
}

UdpmReceiver::UdpmReceiver(const ReassemblyLimits& limits, ChannelFilter filter)
    : rs_(limits, filter),
      kernel_channels_(filter.names()),
      buf_(kBatch * (kMaxDatagramBytes + 1)),
      len_(kBatch),
      from_(kBatch) {}

UdpmReceiver::~UdpmReceiver() {
  if (fd_ >= 0) ::close(fd_);
}

bool socketStepFailed(const LcmUrl& u, const char* step, int* fd, std::string* why) {
  const int err = errno;
  if (why) {
    *why = "LCM URL '" + u.text + "': " + step + ": " + std::strerror(err);
    // joining a group with no route to it (a fresh network namespace) fails here, not at the first send
    if (err == ENODEV) *why += " (no multicast route: ip link set lo up && ip route add 224.0.0.0/4 dev lo)";
  }
  if (*fd >= 0) ::close(*fd);
  *fd = -1;
  return false;
}

bool UdpmReceiver::open(const std::string& url, int recv_buf_bytes, std::string* why) {
  const LcmUrl u = parseLcmUrl(url, why);
  if (u.kind == LcmUrl::Kind::InProcess) return true;
  if (u.kind != LcmUrl::Kind::Udpm) return false;
  auto fail = [&](const char* step) { return socketStepFailed(u, step, &fd_, why); };
  // Blocking: waitDrain() blocks in recvmmsg itself (SO_RCVTIMEO); every other read says MSG_DONTWAIT.
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) return fail("socket");
  const int one = 1;
  if (setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) < 0) return fail("SO_REUSEADDR");
  // A large buffer rides out a burst; root may exceed net.core.rmem_max.
  const int want = u.recv_buf_size > 0 ? u.recv_buf_size : recv_buf_bytes;
  if (want > 0 && setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &want, sizeof want) < 0) {
    setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &want, sizeof want);
  }
  socklen_t len = sizeof rcvbuf_;
  getsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &rcvbuf_, &len);
  // The kernel's count of datagrams dropped because this buffer was full
  // comes with each datagram (SO_RXQ_OVFL): no drop goes uncounted.
  setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof one);
  // Bound to the group, not INADDR_ANY: unicast datagrams to the port and
  // other groups' traffic on it never reach this socket.
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_addr.s_addr = u.group;
  sa.sin_port = htons(u.port);
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&sa), sizeof sa) < 0) return fail("bind");
  ip_mreq mreq{};
  mreq.imr_multiaddr.s_addr = u.group;
  mreq.imr_interface.s_addr = htonl(INADDR_ANY);
  if (setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mreq, sizeof mreq) < 0) return fail("IP_ADD_MEMBERSHIP");
  // A refused filter only costs wake-ups: the reassembler's channel filter still applies.
  std::vector<sock_filter> prog = channelProgram(kernel_channels_);
  if (!prog.empty()) {
    const sock_fprog fp{static_cast<unsigned short>(prog.size()), prog.data()};
    kernel_filter_ = setsockopt(fd_, SOL_SOCKET, SO_ATTACH_FILTER, &fp, sizeof fp) == 0;
  }
  return true;
}

int UdpmReceiver::wait(int timeout_ms, std::int64_t spin_ns) noexcept {
  if (fd_ >= 0 && spin_ns > 0) {
    pollfd p{fd_, POLLIN, 0};
    const std::int64_t until = monotonicNs() + spin_ns;
    do {
      const int r = ::poll(&p, 1, 0);
      if (r != 0) return r > 0 ? 1 : (errno == EINTR ? 0 : -1);
      sched_yield();  // a peer on this CPU gets it at once; alone, this returns at once
    } while (monotonicNs() < until);
  }
  if (fd_ < 0) {
    if (timeout_ms > 0) {
      const timespec ts{timeout_ms / 1000, (timeout_ms % 1000) * 1000000L};
      nanosleep(&ts, nullptr);
    }
    return 0;
  }
  pollfd p{fd_, POLLIN, 0};
  const int r = ::poll(&p, 1, timeout_ms);
  if (r < 0) return errno == EINTR ? 0 : -1;
  return r > 0 ? 1 : 0;
}

int UdpmReceiver::readBatch(int want, int block_ms) noexcept {
  if (fd_ < 0) return 0;
  if (block_ms > 0 && block_ms != rcvtimeo_ms_) {  // set once while the wait stays the same: no call per read
    const timeval tv{block_ms / 1000, (block_ms % 1000) * 1000};
    if (setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv) < 0) {
      ++socket_errors_;
      return -1;
    }
    rcvtimeo_ms_ = block_ms;
  }
  constexpr std::size_t kSlot = kMaxDatagramBytes + 1;
  sockaddr_in from[kBatch];
  iovec iov[kBatch];
  alignas(cmsghdr) char control[kBatch][CMSG_SPACE(sizeof(std::uint32_t))];
  mmsghdr hdr[kBatch];
  for (int i = 0; i < want; ++i) {
    from[i] = sockaddr_in{};
    iov[i] = iovec{buf_.data() + static_cast<std::size_t>(i) * kSlot, kSlot};
    hdr[i] = mmsghdr{};
    hdr[i].msg_hdr.msg_name = &from[i];
    hdr[i].msg_hdr.msg_namelen = sizeof from[i];
    hdr[i].msg_hdr.msg_iov = &iov[i];
    hdr[i].msg_hdr.msg_iovlen = 1;
    hdr[i].msg_hdr.msg_control = control[i];
    hdr[i].msg_hdr.msg_controllen = sizeof control[i];
  }
  // MSG_TRUNC: each datagram's real length, so an oversized one is seen and counted.
  // MSG_WAITFORONE: block (up to SO_RCVTIMEO) for the first only, then take what is waiting.
  const int flags = MSG_TRUNC | (block_ms > 0 ? MSG_WAITFORONE : MSG_DONTWAIT);
  const int n = ::recvmmsg(fd_, hdr, static_cast<unsigned>(want), flags, nullptr);
  if (n < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return 0;
    ++socket_errors_;
    return block_ms > 0 ? -1 : 0;
  }
  batch_utime_ = realtimeUs();
  for (int i = 0; i < n; ++i) {
    len_[static_cast<std::size_t>(i)] = hdr[i].msg_len;
    from_[static_cast<std::size_t>(i)] = Source{from[i].sin_addr.s_addr, from[i].sin_port};
    for (cmsghdr* c = CMSG_FIRSTHDR(&hdr[i].msg_hdr); c != nullptr; c = CMSG_NXTHDR(&hdr[i].msg_hdr, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t total = 0;  // cumulative for the socket
        std::memcpy(&total, CMSG_DATA(c), sizeof total);
        kernel_drops_ = total;
      }
    }
  }
  return n;
}

const Message* UdpmReceiver::feedRead(int i, std::int64_t* recv_utime) noexcept {
  constexpr std::size_t kSlot = kMaxDatagramBytes + 1;
  const std::size_t k = static_cast<std::size_t>(i);
  *recv_utime = batch_utime_;
  if (len_[k] > kSlot) {
    rs_.count(Drop::Truncated);
    return nullptr;
  }
  return rs_.feed(buf_.data() + k * kSlot, len_[k], from_[k], monotonicNs());
}

std::string UdpmReceiver::summary() const {
  const ReassemblyCounters& c = rs_.counters();
  std::ostringstream s;
  s << "datagrams " << c.datagrams << ", messages " << c.messages << " (" << c.reassembled << " reassembled), dropped "
    << c.dropped();
  const char* sep = ": ";
  for (int i = 0; i < kNumDrops; ++i) {
    if (c.drops[i] > 0) {
      s << sep << c.drops[i] << " " << describe(static_cast<Drop>(i));
      sep = ", ";
    }
  }
  if (kernel_filter_) {
    // The kernel adds the filter's drops to the same counter as buffer overflows.
    s << "; " << kernel_drops_ << " dropped in the kernel (other channels' whole messages, by the socket filter, "
      << "and any overflow of the " << rcvbuf_ << "-byte socket buffer: the kernel counts both together)";
  } else {
    s << "; " << kernel_drops_ << " lost in the kernel (socket buffer of " << rcvbuf_ << " bytes full)";
  }
  if (socket_errors_ > 0) s << "; socket errors " << socket_errors_;
  return s.str();
}

}  // namespace gimbalsim::lcm_wire
