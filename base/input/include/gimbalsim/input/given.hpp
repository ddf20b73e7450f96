// The values given for a key table: the document's leaves flattened to
// dotted keys with their file:line:column, the --set overrides laid over them
// ("--set #k 'key=value'"), aliases read as their keys, and the problems
// found, each naming place and key as the user spelled it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/input/input_error.hpp"

namespace YAML {
class Node;
}

namespace gimbalsim {

/// Names for a table's documents in messages.
struct TableWords {
  std::string document;  ///< "a scene": "<origin>: a scene must be a mapping of sections"
  std::string file;      ///< "scene file": "<path>: cannot open scene file"
  std::string see;       ///< where keys are listed: "unknown key 'x' (see `gimbalsim keys`)"
  std::string section;   ///< "" = the whole document; else only this section is read, the rest ignored
};

/// The values given for a table's keys (the document's leaves, then the
/// --set overrides), each with its place, and the problems found so far.
class Given {
 public:
  struct Place;
  /// keys: (key, alternative key or "") in table order. Two alternative keys
  /// set one field: a --set of one drops the other, giving both is refused.
  /// aliases: (old spelling, key): the old spelling is read as the key (giving
  /// both in one file is refused; a --set of either wins) and named as spelled.
  /// printed: the first overrides are a scene's printed values (Scene.replace, a pickled scene): an override
  /// after them may replace their alternative; two alternatives among the rest are refused.
  Given(const TableWords& words, const std::vector<std::pair<std::string, std::string>>& keys,
        const std::string& yaml, const std::string& origin, const std::vector<std::string>& overrides,
        const std::vector<std::pair<std::string, std::string>>& aliases = {}, std::size_t printed = 0);
  ~Given();
  Given(const Given&) = delete;
  Given& operator=(const Given&) = delete;

  /// The document was not read (not YAML, not a mapping): nothing else is checked.
  bool unreadable() const { return unreadable_; }
  bool has(const std::string& key) const;
  /// The key as the user spelled it (an alias, or the key itself).
  std::string named(const std::string& key) const;
  /// Calls set(value) if key was given; a ConvertError is a problem at its place.
  void apply(const std::string& key, const std::function<void(const YAML::Node&)>& set);
  /// "<place>: key '<key>': <msg>", the place where key was given (else where
  /// its alternative was, named so; else "<origin>: (default of <key>)").
  void refuse(const std::string& key, const std::string& msg);
  void warn(const std::string& key, const std::string& msg);
  /// A warning that key acts on nothing here (none for a printed value: said at the scene's load); one given by
  /// a --set is recorded in idle_sets too (a study refuses a --set that acts in none of its runs).
  void idle(const std::string& key, const std::string& msg);
  /// Same, only when a --set gave the key: a scene file (or its printed values) keeps keys its structure leaves
  /// idle (an ideal twin).
  void idleIfSet(const std::string& key, const std::string& msg);
  /// The problem refuse() would record, not recorded: for a value judged after the load (a controller's value
  /// that runs as another is refused by the runs, not by the file).
  Problem problemAt(const std::string& key, const std::string& msg) const;

  std::vector<Problem> problems;
  std::vector<std::string> warnings;
  /// (1-based --set number, "key 'k': why") of each --set found acting on nothing.
  std::vector<std::pair<int, std::string>> idle_sets;

 private:
  /// The place that gave key (or its alternative), with the key as spelled there; nullptr for a default.
  const Place* placeOf(const std::string& key, std::string* spelled) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool unreadable_ = false;
  std::size_t printed_ = 0;  ///< the first overrides are a scene's printed values: its own, as a file's
};

}  // namespace gimbalsim
