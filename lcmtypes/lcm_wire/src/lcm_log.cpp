#include "gimbalsim/lcm_wire/lcm_log.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

namespace gimbalsim::lcm_wire {
namespace {

std::uint64_t be(const std::uint8_t* p, int n) noexcept {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}
void putBe(std::uint8_t* p, std::uint64_t v, int n) noexcept {
  for (int i = n - 1; i >= 0; --i, v >>= 8) p[i] = static_cast<std::uint8_t>(v);
}

}  // namespace

LogReader::~LogReader() {
  if (f_) std::fclose(f_);
}

bool LogReader::open(const std::string& path, std::string* why) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) {
    if (why) *why = "log '" + path + "': " + std::strerror(errno);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    if (why) *why = "log '" + path + "': not a regular file";
    return false;
  }
  f_ = std::fopen(path.c_str(), "rb");
  if (!f_) {
    if (why) *why = "log '" + path + "': cannot open (" + std::strerror(errno) + ")";
    return false;
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
  return true;
}

void LogReader::openMemory(const std::uint8_t* data, std::size_t n) {
  mem_ = data;
  size_ = n;
}

bool LogReader::readAt(std::uint64_t off, void* dst, std::size_t n) {
  if (n == 0) return true;
  if (mem_) {
    std::memcpy(dst, mem_ + off, n);
    return true;
  }
  return std::fseek(f_, static_cast<long>(off), SEEK_SET) == 0 && std::fread(dst, 1, n, f_) == n;
}

std::string LogReader::readError() const {
  const int err = f_ && std::ferror(f_) ? errno : 0;
  return std::string("read error") + (err != 0 ? std::string(" (") + std::strerror(err) + ")" : " (the file shrank)");
}

bool LogReader::fail(std::uint64_t off, const std::string& what, bool truncated) {
  error_ = (truncated ? "truncated LCM log at byte offset " : "malformed LCM log at byte offset ") +
           std::to_string(off) + ": " + what;
  error_offset_ = off;
  truncated_ = truncated;
  done_ = true;
  return false;
}

bool LogReader::next(LogEvent* e) {
  if (done_ || (!f_ && !mem_ && size_ > 0)) return false;
  const std::uint64_t off = pos_;
  if (off == size_) {
    done_ = true;
    return false;
  }
  const std::uint64_t left = size_ - off;
  if (left < kLogHeaderBytes) {
    // A partial header is a cut tail only if what is there still starts like one.
    std::uint8_t part[kLogHeaderBytes] = {};
    if (!readAt(off, part, static_cast<std::size_t>(left))) return fail(off, readError());
    bool sync_prefix = true;
    for (std::uint64_t i = 0; i < left && i < 4; ++i) sync_prefix = sync_prefix && part[i] == ((kLogSync >> (24 - 8 * i)) & 0xFF);
    return fail(off, "truncated event header (" + std::to_string(left) + " of " + std::to_string(kLogHeaderBytes) +
                         " bytes)", sync_prefix);
  }
  std::uint8_t h[kLogHeaderBytes];
  if (!readAt(off, h, sizeof h)) return fail(off, readError());
  const std::uint32_t sync = static_cast<std::uint32_t>(be(h, 4));
  if (sync != kLogSync) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%08X", sync);
    return fail(off, std::string("bad sync word ") + hex + " (expected 0xEDA1DA01)");
  }
  const auto channel_len = static_cast<std::int32_t>(static_cast<std::uint32_t>(be(h + 20, 4)));
  const auto data_len = static_cast<std::int32_t>(static_cast<std::uint32_t>(be(h + 24, 4)));
  if (channel_len < 1 || channel_len > kMaxLogChannelBytes) {
    return fail(off, "channel length " + std::to_string(channel_len) + " outside [1, " +
                         std::to_string(kMaxLogChannelBytes) + "]");
  }
  if (data_len < 0 || data_len > kMaxLogEventBytes) {
    return fail(off, "data length " + std::to_string(data_len) + " outside [0, " + std::to_string(kMaxLogEventBytes) +
                         "]");
  }
  const std::uint64_t body = std::uint64_t(channel_len) + std::uint64_t(data_len);
  if (body > left - kLogHeaderBytes) {
    return fail(off, "event declares " + std::to_string(channel_len) + " channel + " + std::to_string(data_len) +
                         " data bytes, but only " + std::to_string(left - kLogHeaderBytes) +
                         " bytes follow its header in the file", true);
  }
  buf_.resize(static_cast<std::size_t>(body));
  if (!readAt(off + kLogHeaderBytes, buf_.data(), buf_.size())) return fail(off, readError());
  e->offset = off;
  e->eventnum = static_cast<std::int64_t>(be(h + 4, 8));
  e->timestamp = static_cast<std::int64_t>(be(h + 12, 8));
  e->channel = std::string_view(reinterpret_cast<const char*>(buf_.data()), static_cast<std::size_t>(channel_len));
  e->data = buf_.data() + channel_len;
  e->size = static_cast<std::size_t>(data_len);
  pos_ = off + kLogHeaderBytes + body;
  return true;
}

bool LogWriter::write(std::int64_t timestamp_us, std::string_view channel, const std::uint8_t* data, std::size_t n) {
  if (channel.empty() || channel.size() > static_cast<std::size_t>(kMaxLogChannelBytes) ||
      n > static_cast<std::size_t>(kMaxLogEventBytes)) {
    out_of_bounds_ = true;
    return false;
  }
  std::uint8_t h[kLogHeaderBytes];
  putBe(h, kLogSync, 4);
  putBe(h + 4, static_cast<std::uint64_t>(next_), 8);
  putBe(h + 12, static_cast<std::uint64_t>(timestamp_us), 8);
  putBe(h + 20, channel.size(), 4);
  putBe(h + 24, n, 4);
  if (!out_) return false;
  const bool ok = out_->write({reinterpret_cast<const char*>(h), sizeof h}) && out_->write(channel) &&
                  out_->write({reinterpret_cast<const char*>(data), n});
  if (ok) ++next_;
  return ok;
}

bool LogWriter::open(const std::string& path, std::string* why) {
  try {
    out_.emplace(path);
  } catch (const io::OutputError& e) {
    if (why) *why = e.what();
    return false;
  }
  next_ = 0;
  return true;
}

std::string LogWriter::error() const {
  if (out_ && !out_->error().empty()) return out_->error();
  if (out_ && !out_->ok()) return out_->path() + ": a write failed";
  if (out_of_bounds_) return "an event beyond the log format's bounds (channel or payload too long)";
  return out_ ? "" : "the log was never opened";
}

bool LogWriter::commit(std::string* why) {
  if (out_ && out_->commit()) return true;
  if (why) *why = out_ ? out_->error() : "the log was never opened";
  return false;
}

}  // namespace gimbalsim::lcm_wire
