// An output file that is never a truncated result posing as a whole one: the
// bytes go to a temporary file beside the target (created with O_EXCL, so
// never through an existing file or link), every write is checked, and
// commit() flushes, syncs and renames it over the target. Refused at open:
// a target that is a symbolic link, a directory or other non-regular file,
// or the same file as one of the program's inputs. Without commit() (an
// error, an exception) the temporary file is removed.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace gimbalsim::bench_io {

class OutputFile {
 public:
  OutputFile() = default;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile() { abandon(); }

  /// False with *why (naming `path`) when the target is refused or the
  /// temporary cannot be created. `inputs`: files this output must not replace.
  bool open(const std::string& path, std::string* why, const std::vector<std::string>& inputs = {});

  bool isOpen() const noexcept { return f_ != nullptr; }
  std::FILE* file() noexcept { return f_; }
  const std::string& path() const noexcept { return path_; }

  /// Checked writes: false once any write failed (the stream's error flag).
  bool write(const void* data, std::size_t n) noexcept;
  bool puts(const char* s) noexcept;
  bool ok() const noexcept { return f_ != nullptr && !std::ferror(f_); }

  /// Flush, fsync, close, rename over the target. False with *why on failure
  /// (then the target is untouched and the temporary removed).
  bool commit(std::string* why);
  /// Removes the temporary; the target is untouched.
  void abandon() noexcept;

 private:
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
};

/// Why `path` cannot be an output (empty when it can): a symbolic link, not a
/// regular file, or the same file as one of `inputs`.
std::string refuseOutput(const std::string& path, const std::vector<std::string>& inputs);

}  // namespace gimbalsim::bench_io
