#include "gimbalsim/bench_io/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace gimbalsim::bench_io {

std::string refuseOutput(const std::string& path, const std::vector<std::string>& inputs) {
  struct stat st{};
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) return "output '" + path + "' is a symbolic link: refusing to write through it";
    if (!S_ISREG(st.st_mode)) return "output '" + path + "' exists and is not a regular file";
    for (const std::string& in : inputs) {
      struct stat si{};
      if (!in.empty() && ::stat(in.c_str(), &si) == 0 && si.st_dev == st.st_dev && si.st_ino == st.st_ino) {
        return "output '" + path + "' is the input '" + in + "': refusing to overwrite an input";
      }
    }
  }
  return "";
}

bool OutputFile::open(const std::string& path, std::string* why, const std::vector<std::string>& inputs) {
  abandon();
  if (const std::string r = refuseOutput(path, inputs); !r.empty()) {
    if (why) *why = r;
    return false;
  }
  path_ = path;
  tmp_ = path + ".tmp.XXXXXX";
  const int fd = ::mkostemp(tmp_.data(), O_CLOEXEC);  // O_EXCL: a new file, never an existing one
  if (fd < 0) {
    if (why) *why = "output '" + path + "': cannot create a temporary file beside it (" + std::strerror(errno) + ")";
    tmp_.clear();
    return false;
  }
  ::fchmod(fd, 0644);
  f_ = ::fdopen(fd, "w");
  if (f_ == nullptr) {
    ::close(fd);
    ::unlink(tmp_.c_str());
    tmp_.clear();
    if (why) *why = "output '" + path + "': fdopen failed";
    return false;
  }
  return true;
}

bool OutputFile::write(const void* data, std::size_t n) noexcept {
  if (f_ == nullptr) return false;
  if (n > 0 && std::fwrite(data, 1, n, f_) != n) return false;
  return !std::ferror(f_);
}

bool OutputFile::puts(const char* s) noexcept { return write(s, std::strlen(s)); }

bool OutputFile::commit(std::string* why) {
  if (f_ == nullptr) {
    if (why) *why = "output '" + path_ + "': not open";
    return false;
  }
  const bool wrote = !std::ferror(f_) && std::fflush(f_) == 0 && ::fsync(::fileno(f_)) == 0;
  const int err = errno;
  const bool closed = std::fclose(f_) == 0;
  f_ = nullptr;
  if (!wrote || !closed) {
    if (why) *why = "output '" + path_ + "': writing failed (" + std::strerror(wrote ? errno : err) + ")";
    abandon();
    return false;
  }
  // The target may have become a link since open(): rename replaces the link itself.
  if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
    if (why) *why = "output '" + path_ + "': rename of the finished file failed (" + std::strerror(errno) + ")";
    abandon();
    return false;
  }
  tmp_.clear();
  return true;
}

void OutputFile::abandon() noexcept {
  if (f_ != nullptr) {
    std::fclose(f_);
    f_ = nullptr;
  }
  if (!tmp_.empty()) {
    ::unlink(tmp_.c_str());
    tmp_.clear();
  }
}

}  // namespace gimbalsim::bench_io
