// How every gimbalsim program writes a result file: into a temporary beside
// the requested name, every write and the close checked, renamed onto the
// name only when complete. A file under the requested name is therefore
// never a cut-off or corrupt result posing as a whole one. The path policy:
// an existing symbolic link or non-regular file (directory, device, FIFO) is
// refused, and so is an output that is the same file as an input or as
// another output of the same run (st_dev/st_ino of the file or, before it
// exists, of its directory plus its name). No fsync: the rename protects
// against a program that stops half-way, not against a power cut.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gimbalsim::io {

/// A refused or failed output; what() names the file.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Refuses, before anything runs, outputs that break the policy above:
/// each output path on its own, then every pair of outputs and each output
/// against each input. Empty paths are skipped. Throws OutputError.
void checkOutputPaths(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs = {});

/// One output being written. The constructor checks the path (policy above)
/// and creates the temporary "<dir>/.<name>.<pid>.<n>.tmp"; the destructor
/// removes the temporary unless commit() succeeded.
class OutputFile {
 public:
  explicit OutputFile(std::string path);  ///< throws OutputError
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  /// Appends bytes (buffered); false from the first failure on (error() says).
  bool write(std::string_view bytes) noexcept;
  /// Flushes, closes and renames onto path(); false if any of it failed.
  bool commit() noexcept;
  bool ok() const { return error_.empty(); }
  /// "<path>: <reason>", empty while ok.
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }

 private:
  void fail(const char* what) noexcept;
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
  bool committed_ = false;
  std::string error_;
};

/// The whole content at once through an OutputFile; throws OutputError.
void writeFileAtomically(const std::string& path, std::string_view content);

}  // namespace gimbalsim::io
