// The refusal of a text input: every problem found in a scene, a controller
// configuration, a fault schedule or a sweep's arguments, each naming its
// place and key. SceneError, ConfigError and FaultScheduleError derive from
// it, so a program (and the Python package) catches one type.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace gimbalsim {

/// One refusal: the message as printed, and where it points, as fields (for
/// programs: the Python package's SceneError, tests).
struct Problem {
  std::string text;          ///< "<place>: key '<key>': <why>", as printed
  std::string key;           ///< the key refused; "" when none (YAML syntax, not a mapping, unreadable file)
  std::string file;          ///< the document's origin (path); "" for a --set value
  int line = 0, column = 0;  ///< 1-based position in the file; 0 when not a file position
  int set_index = 0;         ///< 1-based --set index; 0 when not from --set
};

class InputError : public std::runtime_error {
 public:
  explicit InputError(std::vector<Problem> problems);
  /// A refusal of the whole document (e.g. "<path>: cannot open scene file").
  explicit InputError(const std::string& problem);
  /// Problems known only as their printed text (readers of other formats).
  explicit InputError(const std::vector<std::string>& texts);
  /// The messages, as printed.
  const std::vector<std::string>& problems() const { return texts_; }
  /// The same with key and place as fields.
  const std::vector<Problem>& details() const { return details_; }

 private:
  std::vector<Problem> details_;
  std::vector<std::string> texts_;
};

/// The problems as printed, each place "--set #k 'key=value'" replaced by
/// labels[k - 1] when that is given: a program that turns its own flags into
/// overrides names the flag (or the user's --set by the user's own count).
std::vector<std::string> relabelledProblems(const InputError& e, const std::vector<std::string>& labels);

}  // namespace gimbalsim
