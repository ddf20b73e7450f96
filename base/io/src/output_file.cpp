#include "gimbalsim/io/output_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>

namespace gimbalsim::io {

namespace {

std::string dirOf(const std::string& path) {
  const auto slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string baseOf(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// The file a path names: (device, inode) of the file if it exists, else of
/// its directory plus its name, so two spellings of one new file compare equal.
struct Identity {
  dev_t dev = 0;
  ino_t ino = 0;
  std::string name;  ///< "" when the file exists
  bool operator==(const Identity&) const = default;
};

bool identify(const std::string& path, Identity& id) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    id = {st.st_dev, st.st_ino, ""};
    return true;
  }
  if (::stat(dirOf(path).c_str(), &st) != 0) return false;
  id = {st.st_dev, st.st_ino, baseOf(path)};
  return true;
}

/// The files of this process's code: the executable, the loader and every shared library mapped
/// (/proc/self/maps), each with its identity. (pass 105) --out over a loaded libyaml-cpp replaced it; every later
/// run of every program failed to start.
std::vector<std::pair<std::string, Identity>> mappedCodeFiles() {
  std::ifstream maps("/proc/self/maps");
  std::set<std::string> paths;
  for (std::string line; std::getline(maps, line);) {
    const auto slash = line.find('/');
    if (slash != std::string::npos) paths.insert(line.substr(slash));
  }
  std::vector<std::pair<std::string, Identity>> out;
  for (const std::string& path : paths) {
    if (Identity mapped; identify(path, mapped) && mapped.name.empty()) out.emplace_back(path, mapped);
  }
  return out;
}

/// Where anything run by name finds the executable file path (stat st) as a program: "in F, a folder on PATH",
/// or "run as F/name on PATH" (a link or a hard link to it there); "" when it is none. (pass 103, 107) the
/// scripts' lists of the programs they run by name always missed one (realpath, rmdir); (pass 108) a link in a
/// PATH folder made a file elsewhere a program.
std::string programOnPath(const std::string& path, const struct stat& st) {
  const char* env = std::getenv("PATH");
  struct stat folder {};
  if (!env || (st.st_mode & 0111) == 0 || ::stat(dirOf(path).c_str(), &folder) != 0) return "";
  const std::string list = env;
  for (std::size_t start = 0; start <= list.size();) {
    const std::size_t end = std::min(list.find(':', start), list.size());
    const std::string entry = end > start ? list.substr(start, end - start) : ".";  // "" is the current folder
    start = end + 1;
    struct stat on_path {};
    if (::stat(entry.c_str(), &on_path) != 0) continue;
    if (on_path.st_dev == folder.st_dev && on_path.st_ino == folder.st_ino) return "in " + entry + ", a folder on PATH";
    const std::unique_ptr<DIR, int (*)(DIR*)> dir(::opendir(entry.c_str()), ::closedir);
    for (const dirent* e = dir ? ::readdir(dir.get()) : nullptr; e != nullptr; e = ::readdir(dir.get())) {
      struct stat named {};
      if (e->d_type != DT_DIR && ::stat((entry + "/" + e->d_name).c_str(), &named) == 0 &&
          named.st_dev == st.st_dev && named.st_ino == st.st_ino) {
        return "run as " + entry + "/" + e->d_name + " on PATH";
      }
    }
  }
  return "";
}

/// The checks of one output path on its own; throws OutputError.
void checkOne(const std::string& path) {
  if (path.empty()) throw OutputError("output path is empty");
  if (baseOf(path).empty() || baseOf(path) == "." || baseOf(path) == "..") {
    throw OutputError(path + ": not a file name");
  }
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) throw OutputError(path + ": is a symbolic link; not written through (give its target)");
    if (!S_ISREG(st.st_mode)) throw OutputError(path + ": exists and is not a regular file; not written");
    if (const std::string where = programOnPath(path, st); !where.empty()) {
      throw OutputError(path + ": an executable file " + where + " (a program anything run by name may be); not "
                        "overwritten");
    }
  } else if (errno != ENOENT) {
    throw OutputError(path + ": " + std::strerror(errno));
  }
  struct stat dir {};
  if (::stat(dirOf(path).c_str(), &dir) != 0 || !S_ISDIR(dir.st_mode)) {
    throw OutputError(path + ": its directory " + dirOf(path) + " does not exist");
  }
}

}  // namespace

void checkOutputPaths(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
  std::vector<std::pair<std::string, Identity>> seen, code;
  for (const std::string& out : outputs) {
    if (out.empty()) continue;
    checkOne(out);
    Identity id;
    if (!identify(out, id)) throw OutputError(out + ": " + std::strerror(errno));
    for (const auto& [other, oid] : seen) {
      if (oid == id) throw OutputError(out + ": the same file as another output (" + other + ")");
    }
    for (const std::string& in : inputs) {
      Identity iid;
      if (!in.empty() && identify(in, iid) && iid == id) {
        throw OutputError(out + ": the same file as the input " + in + "; not overwritten");
      }
    }
    // The running program is an input of every run: `gimbalsim simulate --out <itself>` replaced it (pass 84).
    if (Identity self; identify("/proc/self/exe", self) && self == id) {
      throw OutputError(out + ": the same file as this program (the executable running); not overwritten");
    }
    if (code.empty()) code = mappedCodeFiles();  // read once per call, and only when there is an output
    for (const auto& [path, mapped] : code) {
      if (mapped == id) throw OutputError(out + ": the same file as " + path + ", a library this program runs; not "
                                          "overwritten");
    }
    seen.emplace_back(out, id);
  }
}

OutputFile::OutputFile(std::string path, const std::vector<std::string>& inputs) : path_(std::move(path)) {
  if (path_.empty()) throw OutputError("output path is empty");
  checkOutputPaths({path_}, inputs);
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 100 && !f_; ++attempt) {
    tmp_ = dirOf(path_) + "/." + baseOf(path_) + "." + std::to_string(::getpid()) + "." +
           std::to_string(counter++) + ".tmp";
    // O_EXCL | O_NOFOLLOW: a fresh file of our own, never an existing one or a link's target.
    const int fd = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST) continue;
      throw OutputError(path_ + ": cannot create a temporary in " + dirOf(path_) + ": " + std::strerror(errno), true);
    }
    f_ = ::fdopen(fd, "wb");
    if (!f_) {
      const int err = errno;
      ::close(fd);
      ::unlink(tmp_.c_str());
      throw OutputError(path_ + ": " + std::strerror(err), true);
    }
  }
  if (!f_) throw OutputError(path_ + ": cannot create a temporary (100 names taken)", true);
}

OutputFile::~OutputFile() {
  if (!committed_) discard();
}

void OutputFile::discard() noexcept {
  if (f_) std::fclose(f_);
  f_ = nullptr;
  if (!tmp_.empty()) ::unlink(tmp_.c_str());
  tmp_.clear();
}

void OutputFile::fail(const char* what, int err) noexcept {
  if (!error_.empty()) return;
  try {
    error_ = path_ + ": " + what + (err != 0 ? std::string(": ") + std::strerror(err) : std::string());
  } catch (...) {
  }
}

bool OutputFile::write(std::string_view bytes) noexcept {
  if (!ok() || !f_) return false;
  if (std::fwrite(bytes.data(), 1, bytes.size(), f_) != bytes.size()) fail("write failed", errno);
  return ok();
}

bool OutputFile::commit() noexcept { return seal() && publish(); }

bool OutputFile::seal() noexcept {
  if (!f_ || committed_ || sealed_) return false;
  const bool stream_failed = std::ferror(f_) != 0;
  // A failed formatted write (stream()) leaves the flag; flushing again gives its errno.
  if (error_.empty() && std::fflush(f_) != 0) fail("write failed", errno);
  if (error_.empty() && stream_failed) fail("write failed", 0);
  if (error_.empty() && ::fsync(::fileno(f_)) != 0) fail("sync failed", errno);
  const bool closed = std::fclose(f_) == 0;
  const int close_err = errno;
  f_ = nullptr;
  if (error_.empty() && !closed) fail("close failed", close_err);
  sealed_ = error_.empty();
  if (!sealed_) discard();
  return sealed_;
}

bool OutputFile::publish() noexcept {
  if (!sealed_ || committed_) return false;
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) fail("rename failed", errno);
  committed_ = error_.empty();
  if (!committed_) discard();
  return committed_;
}

void OutputFile::withdraw() noexcept {
  if (!committed_) return;
  ::unlink(path_.c_str());
  committed_ = false;
  tmp_.clear();  // renamed away: nothing left to discard
}

bool CommitGroup::commit() noexcept {
  auto failWith = [&](const OutputFile& f) {
    try {
      error_ = f.error().empty() ? f.path() + ": not committed" : f.error();
    } catch (...) {
    }
    for (OutputFile* g : files_) {
      if (g) g->withdraw();  // published ones leave their name; the destructors remove the temporaries
    }
    return false;
  };
  for (OutputFile* f : files_) {
    if (f && !f->seal()) return failWith(*f);
  }
  for (OutputFile* f : files_) {
    if (f && !f->publish()) return failWith(*f);
  }
  return true;
}

void writeFileAtomically(const std::string& path, std::string_view content) {
  OutputFile f(path);
  f.write(content);
  if (!f.commit()) throw OutputError(f.error(), true);
}

void writeFilesTogether(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::unique_ptr<OutputFile>> open;
  std::vector<OutputFile*> members;
  for (const auto& [path, content] : files) {
    open.push_back(std::make_unique<OutputFile>(path));
    open.back()->write(content);
    members.push_back(open.back().get());
  }
  CommitGroup group(members);
  if (!group.commit()) throw OutputError(group.error(), true);
}

std::string outputFolderProblem(const std::string& dir, bool named_by_user) {
  std::error_code ec;
  // A linked folder writes wherever the link points (pass 66): named, never followed, as the package's --out.
  if (std::filesystem::is_symlink(dir, ec)) {
    return "is a link (to " + std::filesystem::read_symlink(dir, ec).string() + "): name the folder itself";
  }
  if (!named_by_user && !std::filesystem::is_directory(dir, ec)) {
    std::filesystem::create_directories(dir, ec);
    if (ec) return "cannot make it: " + ec.message();
  }
  if (std::filesystem::is_directory(dir, ec)) return "";
  return std::filesystem::exists(dir, ec) ? "not a folder" : "no such folder (create it first)";
}

std::string holdOutputFolder(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return std::string("cannot open it: ") + std::strerror(errno);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd);
    return "another run is writing this folder; wait for it to end, or give another";
  }
  return "";  // fd stays open: the lock lasts as long as the process
}

}  // namespace gimbalsim::io
