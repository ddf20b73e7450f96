// LCM's event-log file format (lcm/eventlog.c; lcm-logger, lcm-logplayer,
// lcm-spy): a sequence of events, each a 28-byte big-endian header (sync word
// 0xEDA1DA01, int64 event number, int64 timestamp [us], int32 channel length,
// int32 data length) followed by the channel name (no NUL) and the data.
//
// Why our own reader: LCM 1.3.1's reader trusts the header's lengths (a huge
// data length makes it allocate and read past the file, and crash). This one
// validates every header before reading the event: the sync word, the channel
// length in [1, kMaxLogChannelBytes] and the data length in [0,
// kMaxLogEventBytes], and both within the bytes left in the file. A malformed
// log stops the read with a message naming the byte offset of the bad event;
// a log that merely ends inside its last event (a killed logger) says so
// (truncated()), so a caller can keep the whole events before it.
// Memory: one event at a time, at most kMaxLogChannelBytes + kMaxLogEventBytes.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gimbalsim/io/output_file.hpp"

namespace gimbalsim::lcm_wire {

inline constexpr std::uint32_t kLogSync = 0xEDA1DA01;
inline constexpr std::size_t kLogHeaderBytes = 28;
inline constexpr std::int32_t kMaxLogChannelBytes = 999;           ///< as LCM's own reader (< 1000)
inline constexpr std::int32_t kMaxLogEventBytes = 1 << 28;         ///< LCM_MAX_MESSAGE_SIZE (256 MiB)

struct LogEvent {
  std::uint64_t offset = 0;     ///< byte offset of the event's header in the file
  std::int64_t eventnum = 0;
  std::int64_t timestamp = 0;   ///< [us]
  std::string_view channel;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

class LogReader {
 public:
  LogReader() = default;
  LogReader(const LogReader&) = delete;
  LogReader& operator=(const LogReader&) = delete;
  ~LogReader();

  /// Opens a log: a regular, readable file. False with *why.
  bool open(const std::string& path, std::string* why);
  /// Reads from memory instead (the fuzz target, tests).
  void openMemory(const std::uint8_t* data, std::size_t n);

  /// The next event, valid until the next call. False at the end of the file
  /// or at a malformed event: then error() is non-empty and names the offset.
  bool next(LogEvent* e);
  const std::string& error() const noexcept { return error_; }
  std::uint64_t errorOffset() const noexcept { return error_offset_; }
  /// The error is a cut tail: the file ends inside the event at errorOffset()
  /// (a header or body shorter than declared), as a killed logger leaves it;
  /// every event before it was whole. cutBytes(): the bytes of that partial event.
  bool truncated() const noexcept { return truncated_; }
  std::uint64_t cutBytes() const noexcept { return truncated_ ? size_ - error_offset_ : 0; }
  std::uint64_t fileSize() const noexcept { return size_; }

 private:
  bool readAt(std::uint64_t off, void* dst, std::size_t n);
  std::string readError() const;  ///< "read error (<strerror>)" after a failed readAt
  bool fail(std::uint64_t off, const std::string& what, bool truncated = false);

  std::FILE* f_ = nullptr;
  const std::uint8_t* mem_ = nullptr;
  std::uint64_t size_ = 0, pos_ = 0;
  std::vector<std::uint8_t> buf_;
  std::string error_;
  std::uint64_t error_offset_ = 0;
  bool truncated_ = false;
  bool done_ = false;
};

/// Writes events in the same format (the recorder), through io::OutputFile:
/// the log appears under its name only when committed whole.
class LogWriter {
 public:
  /// False with *why (naming the file) when the output is refused.
  bool open(const std::string& path, std::string* why);
  /// False when the event is out of the format's bounds or the write failed.
  bool write(std::int64_t timestamp_us, std::string_view channel, const std::uint8_t* data, std::size_t n);
  /// Flush, sync, rename; false with *why (the file is then not replaced).
  bool commit(std::string* why);
  std::int64_t events() const noexcept { return next_; }
  /// Why the last write() failed, naming the file ("" while none did).
  std::string error() const;

 private:
  std::optional<io::OutputFile> out_;
  bool out_of_bounds_ = false;  ///< a write() refused an event beyond the format's bounds
  std::int64_t next_ = 0;
};

}  // namespace gimbalsim::lcm_wire
