// How every gimbalsim program writes a result file (the command line, the
// tools, firmware_sim's CSVs, the recorder, log2csv, the controller's log, the
// Python package): into a temporary beside the requested name, every write
// checked, flushed, synced and renamed onto the name only when complete. A
// file under the requested name is therefore never a cut-off or corrupt result
// posing as a whole one, not even after a power cut (fsync before rename).
// The path policy: an existing symbolic link or non-regular file (directory,
// device, FIFO) is refused, and so is an output that is the same file as an
// input or as another output of the same run (st_dev/st_ino of the file or,
// before it exists, of its directory plus its name). A run with several
// outputs commits them as one CommitGroup: all of them, or none.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gimbalsim::io {

/// A refused or failed output; what() names the file. unwritable(): the path
/// was allowed but the file could not be made or written (a read-only or full
/// folder: exit 4), else the path breaks the policy (a refused argument: exit 2).
struct OutputError : std::runtime_error {
  explicit OutputError(const std::string& what, bool unwritable = false)
      : std::runtime_error(what), unwritable_(unwritable) {}
  bool unwritable() const noexcept { return unwritable_; }

 private:
  bool unwritable_;
};

/// Refuses, before anything runs, outputs that break the policy above:
/// each output path on its own, then every pair of outputs and each output
/// against each input. Empty paths are skipped. Throws OutputError.
void checkOutputPaths(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs = {});

/// The output folder of a tool: one the user named must already exist (a
/// typo must not scatter results into a new folder), the default one is
/// made. Returns "" when dir is a folder now, else why not ("no such folder
/// (create it first)", "not a folder", "is a link (to T): name the folder
/// itself", or the reason it could not be made).
std::string outputFolderProblem(const std::string& dir, bool named_by_user);

/// One writer per output folder: an exclusive lock on the folder itself
/// (flock, no lock file among the outputs), held until the process ends,
/// the same lock the Python sweeps and tuner take. Returns "" when held,
/// else why not ("another run is writing this folder ...").
std::string holdOutputFolder(const std::string& dir);

/// One output being written. The constructor checks the path against the
/// policy and against `inputs`, and creates the temporary
/// "<dir>/.<name>.<pid>.<n>.tmp"; the destructor removes the temporary unless
/// commit() succeeded. Only the constructor throws: writes and commit report
/// by return value, so a real-time loop can write rows without exceptions.
class OutputFile {
 public:
  explicit OutputFile(std::string path, const std::vector<std::string>& inputs = {});  ///< throws OutputError
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  /// Appends bytes (buffered); false from the first failure on (error() says).
  bool write(std::string_view bytes) noexcept;
  /// The open stream, for formatted writers (fprintf); a failure there sets
  /// the stream's error flag, which ok() and commit() see. Null after commit().
  std::FILE* stream() noexcept { return f_; }
  /// Flushes, syncs, closes and renames onto path(); false if any of it or
  /// any earlier write failed (then the name is untouched, the temporary gone).
  /// The same as seal() then publish().
  bool commit() noexcept;
  /// Phase one of commit(): flushes, syncs and closes the temporary, which stays.
  bool seal() noexcept;
  /// Phase two: renames the sealed temporary onto path().
  bool publish() noexcept;
  /// After publish(): removes the file under path() again (a CommitGroup
  /// member whose partner could not be published).
  void withdraw() noexcept;
  /// No write has failed so far (the stream's error flag included).
  bool ok() const noexcept { return error_.empty() && !(f_ && std::ferror(f_)); }
  /// "<path>: <reason>", empty while ok (a failed formatted write is named at commit()).
  const std::string& error() const noexcept { return error_; }
  const std::string& path() const noexcept { return path_; }

 private:
  void fail(const char* what, int err) noexcept;
  void discard() noexcept;
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
  bool sealed_ = false;
  bool committed_ = false;
  std::string error_;
};

/// The outputs of one run, which appear together or not at all: commit()
/// seals every file, then publishes them one by one; when a seal or a rename
/// fails, the files already published are withdrawn and the temporaries
/// removed, so nothing is left under any requested name.
class CommitGroup {
 public:
  /// The members (null ones are skipped); they must outlive the group's commit().
  explicit CommitGroup(std::vector<OutputFile*> files) : files_(std::move(files)) {}
  /// True when every member is under its name; false: error() names the first failure.
  bool commit() noexcept;
  const std::string& error() const noexcept { return error_; }

 private:
  std::vector<OutputFile*> files_;
  std::string error_;
};

/// The whole content at once through an OutputFile; throws OutputError.
void writeFileAtomically(const std::string& path, std::string_view content);

/// Several whole files (path, content) as one CommitGroup: all or none;
/// throws OutputError naming the first file that failed.
void writeFilesTogether(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace gimbalsim::io
