// The values given for a key table (given.hpp): one file reader, one --set
// parser, one place format; and loadDocument, the same bounds for other documents.
#include "gimbalsim/input/given.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <set>

#include "bounded_yaml.hpp"
#include "gimbalsim/input/input_bounds.hpp"
#include "gimbalsim/input/value_convert.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim {

/// Where a value was given: a file position or a --set index.
struct Given::Place {
  std::string file;          ///< origin; "" for --set
  int line = 0, column = 0;  ///< 1-based; 0 = none
  int set_index = 0;         ///< 1-based; 0 = not --set
  std::string set_text;      ///< the --set argument

  static Place inFile(const std::string& origin, int line = 0, int column = 0) {
    Place p;
    p.file = origin;
    p.line = line;
    p.column = column;
    return p;
  }
  static Place inSet(int index, const std::string& text) {
    Place p;
    p.set_index = index;
    p.set_text = text;
    return p;
  }

  std::string str() const {
    if (set_index > 0) return "--set #" + std::to_string(set_index) + " '" + shownText(set_text) + "'";
    if (line > 0) return file + ":" + std::to_string(line) + ":" + std::to_string(column);
    return file;
  }
  /// "<place>: <msg>" as a Problem about `key`.
  Problem problem(const std::string& key, const std::string& msg) const {
    return {str() + ": " + msg, key, set_index > 0 ? "" : file, line, column, set_index};
  }
};

namespace {
struct Value {
  YAML::Node node;
  Given::Place where;
  std::string spelled;  ///< the alias it was given as; "" = the key itself
};
}  // namespace

struct Given::Impl {
  std::map<std::string, Value> values;
  std::map<std::string, std::string> alternative;
  std::string origin;
};

namespace {

Given::Place place(const std::string& origin, const YAML::Mark& mk) {
  if (mk.line < 0) return Given::Place::inFile(origin);
  return Given::Place::inFile(origin, mk.line + 1, mk.column + 1);
}

/// Leaves of nested sections as "a.b" -> (value, place of its key); a key
/// given twice is a problem at its second place (yaml-cpp keeps one silently).
/// An empty mapping is a leaf too: a key given {} is refused by its reader
/// (pass 42: it was skipped, and the key ran at its default), an empty section dropped later.
void flatten(const YAML::Node& n, const std::string& prefix, const std::string& origin,
             std::map<std::string, Value>& out, std::vector<Problem>& problems) {
  for (const auto& kv : n) {
    const std::string full = (prefix.empty() ? "" : prefix + ".") + kv.first.Scalar();
    if (kv.second.IsMap() && kv.second.size() > 0) {
      flatten(kv.second, full, origin, out, problems);
    } else if (const auto [it, fresh] = out.try_emplace(full, Value{kv.second, place(origin, kv.first.Mark()), ""});
               !fresh) {
      problems.push_back(place(origin, kv.first.Mark())
                             .problem(full, "key '" + shownText(full) + "': given twice (first at " +
                                                it->second.where.str() + ")"));
    }
  }
}

}  // namespace

Given::Given(const TableWords& words, const std::vector<std::pair<std::string, std::string>>& keys,
             const std::string& yaml, const std::string& origin, const std::vector<std::string>& overrides,
             const std::vector<std::pair<std::string, std::string>>& aliases, std::size_t printed)
    : impl_(std::make_unique<Impl>()), printed_(printed) {
  impl_->origin = origin;
  auto& values = impl_->values;
  YAML::Node root;
  if (Problem why; !loadDocument(yaml, origin, root, why)) {
    problems.push_back(std::move(why));
  } else if (root.IsMap()) {
    flatten(root, "", origin, values, problems);
  } else if (root.IsDefined() && !root.IsNull()) {
    problems.push_back(Place::inFile(origin).problem("", words.document + " must be a mapping of sections"));
  }
  if (!problems.empty()) {
    unreadable_ = true;
    return;
  }
  std::set<std::string> known;
  for (const auto& [key, alt] : keys) {
    known.insert(key);
    if (!alt.empty()) impl_->alternative[key] = alt;
  }
  const std::map<std::string, std::string> alias_of(aliases.begin(), aliases.end());
  // A file's old spellings are read as their keys; both spellings of one key is a key given twice.
  for (const auto& [alias, key] : alias_of) {
    const auto a = values.find(alias);
    if (a == values.end()) continue;
    Value v = std::move(a->second);
    values.erase(a);
    v.spelled = alias;
    if (const auto k = values.find(key); k != values.end()) {
      const bool alias_first = v.where.line < k->second.where.line ||
                               (v.where.line == k->second.where.line && v.where.column < k->second.where.column);
      const Value& later = alias_first ? k->second : v;
      const Value& first = alias_first ? v : k->second;
      const std::string name = later.spelled.empty() ? key : later.spelled;
      problems.push_back(later.where.problem(name, "key '" + shownText(name) + "': given twice (as '" +
                                                      (first.spelled.empty() ? key : first.spelled) + "' at " +
                                                      first.where.str() + "; " + alias + " is another name of " +
                                                      key + ")"));
      continue;
    }
    values.emplace(key, std::move(v));
  }
  auto unknown = [&](const Place& where, const std::string& key) {
    problems.push_back(where.problem(key, "unknown key '" + shownText(key) + "' (see " + words.see + ")"));
  };
  const std::string& only = words.section;
  const auto is_section = [&](const std::string& name) {  // a prefix of a known key: "contact" of "contact.mu"
    const auto k = known.lower_bound(name + ".");
    return k != known.end() && k->rfind(name + ".", 0) == 0;
  };
  for (auto it = values.begin(); it != values.end();) {
    if (!only.empty() && it->first != only && it->first.rfind(only + ".", 0) != 0) {
      it = values.erase(it);  // another reader's section
    } else if (known.count(it->first)) {
      ++it;
    } else if (it->second.node.IsMap() && is_section(it->first)) {
      it = values.erase(it);  // an empty section ("contact: {}"): nothing given
    } else {
      unknown(it->second.where, it->first);
      it = values.erase(it);
    }
  }
  if (overrides.size() > InputBounds::kMaxOverrides) {
    problems.push_back(Place::inSet(static_cast<int>(InputBounds::kMaxOverrides + 1), "")
                           .problem("", "more than " + std::to_string(InputBounds::kMaxOverrides) + " --set values"));
    return;
  }
  std::map<std::string, std::string> set_here;  // key -> its spelling, for the keys the user's overrides set
  for (std::size_t i = 0; i < overrides.size(); ++i) {
    const std::string& o = overrides[i];
    if (o.size() > InputBounds::kMaxSetBytes) {
      const Place where = Place::inSet(static_cast<int>(i + 1), o.substr(0, 40) + "...");
      problems.push_back(where.problem("", "a --set value of " + std::to_string(o.size()) + " bytes (at most " +
                                               std::to_string(InputBounds::kMaxSetBytes) + ")"));
      continue;
    }
    const Place where = Place::inSet(static_cast<int>(i + 1), o);
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0) {
      problems.push_back(where.problem("", "expected key=value"));
      continue;
    }
    const std::string spelled = o.substr(0, eq);
    const std::string text = o.substr(eq + 1);
    if (!text.empty() && (std::isspace(static_cast<unsigned char>(text.front())) ||
                          std::isspace(static_cast<unsigned char>(text.back())))) {
      // YAML drops the blank of "key= 0.1" silently, where every program's flags refuse ' 0.1'
      problems.push_back(
          where.problem(spelled, "key '" + shownText(spelled) + "': a blank around the value: write key=value"));
      continue;
    }
    const auto alias = alias_of.find(spelled);
    const std::string key = alias == alias_of.end() ? spelled : alias->second;
    if (!known.count(key)) {
      unknown(where, key);
      continue;
    }
    try {
      Value v{loadBounded(text), where, alias == alias_of.end() ? "" : spelled};
      if (auto a = impl_->alternative.find(key); a != impl_->alternative.end()) {
        // Both alternatives among the user's overrides: the later was taken while a summary listed both (pass
        // 71). One replaces its alternative given in the file or among a scene's printed values.
        if (const auto other = set_here.find(a->second); other != set_here.end()) {
          problems.push_back(where.problem(spelled, "key '" + shownText(spelled) + "': sets the same field as '" +
                                                        other->second + "', given before it: give one of them"));
          continue;
        }
        values.erase(a->second);
      }
      if (i >= printed) set_here[key] = spelled;
      values[key] = std::move(v);  // a later --set of the same key wins
    } catch (const PrescanRefusal& r) {
      problems.push_back(where.problem(spelled, "key '" + shownText(spelled) + "': " + r.msg));
    } catch (const YAML::Exception& e) {
      problems.push_back(where.problem(spelled, "key '" + shownText(spelled) + "': value is not valid YAML: " + e.msg));
    } catch (const std::exception& e) {
      problems.push_back(
          where.problem(spelled, "key '" + shownText(spelled) + "': value not readable as YAML: " + e.what()));
    }
  }
  std::set<std::string> seen;
  for (const auto& [key, alt] : keys) {
    if (seen.count(alt) && has(key) && has(alt)) {
      problems.push_back(values[key].where.problem(named(key), "key '" + shownText(named(key)) + "': give it or '" +
                                                                         named(alt) + "', not both"));
    }
    seen.insert(key);
  }
}

Given::~Given() = default;

bool Given::has(const std::string& key) const { return impl_->values.count(key) > 0; }

void Given::apply(const std::string& key, const std::function<void(const YAML::Node&)>& set) {
  const auto it = impl_->values.find(key);
  if (it == impl_->values.end()) return;
  try {
    set(it->second.node);
  } catch (const ConvertError& e) {
    problems.push_back(it->second.where.problem(named(key), "key '" + shownText(named(key)) + "': " + e.msg));
  } catch (const YAML::Exception& e) {
    problems.push_back(it->second.where.problem(named(key), "key '" + shownText(named(key)) + "': " + e.msg));
  }
}

std::string Given::named(const std::string& key) const {
  const auto it = impl_->values.find(key);
  return it == impl_->values.end() || it->second.spelled.empty() ? key : it->second.spelled;
}

const Given::Place* Given::placeOf(const std::string& key, std::string* spelled) const {
  const auto& v = impl_->values;
  std::string given = key;
  if (v.find(key) == v.end()) {
    const auto a = impl_->alternative.find(key);
    if (a == impl_->alternative.end() || v.find(a->second) == v.end()) return nullptr;
    given = a->second;
  }
  *spelled = named(given);
  return &v.find(given)->second.where;
}

Problem Given::problemAt(const std::string& key, const std::string& msg) const {
  std::string spelled;
  if (const Place* p = placeOf(key, &spelled)) return p->problem(spelled, "key '" + shownText(spelled) + "': " + msg);
  return Place::inFile(impl_->origin).problem(key, "(default of " + key + "): key '" + key + "': " + msg);
}

void Given::refuse(const std::string& key, const std::string& msg) { problems.push_back(problemAt(key, msg)); }

void Given::warn(const std::string& key, const std::string& msg) { warnings.push_back(problemAt(key, msg).text); }

void Given::idle(const std::string& key, const std::string& msg) {
  std::string spelled;
  const Place* p = placeOf(key, &spelled);
  // a scene's printed values (Scene.replace, unpickling) are its own: what they leave idle was said at its
  // load, and a default printed for a key the file never gave (a planar scene's bearing length) is no one's
  if (p && p->set_index > 0 && p->set_index <= static_cast<int>(printed_)) return;
  const std::string text = problemAt(key, msg).text;
  // a key and its alternative (journal_radius, clearance) name one given value: said once
  if (std::find(warnings.begin(), warnings.end(), text) != warnings.end()) return;
  warnings.push_back(text);
  if (p && p->set_index > static_cast<int>(printed_)) {
    idle_sets.emplace_back(p->set_index, "key '" + shownText(spelled) + "': " + msg);
  }
}

void Given::idleIfSet(const std::string& key, const std::string& msg) {
  std::string spelled;
  if (const Place* p = placeOf(key, &spelled); p && p->set_index > static_cast<int>(printed_)) idle(key, msg);
}

bool loadDocument(const std::string& text, const std::string& origin, YAML::Node& out, Problem& why) {
  try {
    out = loadBounded(text);
    return true;
  } catch (const PrescanRefusal& r) {
    why = place(origin, r.mark).problem(r.key, (r.key.empty() ? "" : "key '" + shownText(r.key) + "': ") + r.msg);
  } catch (const YAML::Exception& e) {
    why = place(origin, e.mark).problem("", "not valid YAML: " + e.msg);
  } catch (const std::exception& e) {
    why = Given::Place::inFile(origin).problem("", "not readable as YAML: " + std::string(e.what()));
  }
  return false;
}

}  // namespace gimbalsim
