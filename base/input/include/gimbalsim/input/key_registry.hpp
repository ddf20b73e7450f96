// One key registry for the YAML files the programs read (scene files,
// controller configurations): a KeyTable<Target> lists every key with its
// type, unit, check, default and meaning, and binds it to a field of Target.
// The loaders, `gimbalsim keys`, `pointing_controller --keys` and the README
// key tables all come from one. Defaults are read from a default-constructed
// Target: the struct initializers are their source (a shipped file that
// repeats them, controllers/config/default.yaml, is held equal by a test).
//
// Loading (loadKeys): the YAML text's nested sections are flattened to dotted
// keys with their file:line:column, then the `--set key=value` overrides
// (place "--set #k 'key=value'") are laid over them; every key given is
// converted and set in table order, every key's own check is run on the
// result (given or default), and if all passed, the table's validate() checks
// across keys. Every problem is collected, each naming place and key.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "gimbalsim/input/given.hpp"
#include "gimbalsim/input/input_bounds.hpp"
#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/input/value_checks.hpp"
#include "gimbalsim/input/value_convert.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace YAML {
class Node;
}

namespace gimbalsim {

/// A key as the listings and the README show it.
struct KeyInfo {
  std::string key, type, unit, check, default_value, meaning;
};

/// One key bound to a field of Target.
template <class Target>
struct Key {
  Key() = default;
  Key(std::string k, std::string t, std::string u, std::string c, std::string m)
      : key(std::move(k)), type(std::move(t)), unit(std::move(u)), check(std::move(c)), meaning(std::move(m)) {}
  std::string key, type, unit, check, meaning;
  std::function<void(Target&, const YAML::Node&)> set;  ///< throws ConvertError
  std::function<std::string(const Target&)> get;       ///< value as --set reads it; none for derived keys
  std::function<std::string(const Target&)> refusal;   ///< why `check` fails, "" if it holds; none if no check
  /// values() prints the key only where this holds (none: always): a key
  /// that only repeats another's value is left out, so that an override of
  /// the other still acts when the values are read back.
  std::function<bool(const Target&)> present;
  std::string alternative;                             ///< another key setting the same field

  Key alternativeTo(std::string other) const {
    Key k = *this;
    k.alternative = std::move(other);
    return k;
  }
};

template <class Target>
struct KeyTable {
  TableWords words;
  std::vector<Key<Target>> keys;
  /// Checks across keys, run when every key passed its own check.
  std::function<void(const Target&, Given&)> validate;
  /// Derived keys resolved once every key is set (so a key standing for
  /// another, e.g. contact.clearance, does not depend on the table's order).
  std::function<void(Target&, const Given&)> derive;
  /// Old spellings still read: (alias, key), listed in the key docs.
  std::vector<std::pair<std::string, std::string>> aliases;

  /// Every key, its default read from Target{}.
  std::vector<KeyInfo> info() const {
    const Target d{};
    std::vector<KeyInfo> out;
    for (const auto& k : keys) out.push_back({k.key, k.type, k.unit, k.check, k.get ? k.get(d) : "", k.meaning});
    return out;
  }
  /// "key=value" for every key with a value, as --set reads them back.
  std::vector<std::string> values(const Target& t) const {
    std::vector<std::string> out;
    for (const auto& k : keys) {
      if (k.get && (!k.present || k.present(t))) out.push_back(k.key + "=" + k.get(t));
    }
    return out;
  }
};

/// Loads YAML text and overrides onto a default Target; throws Error(problems).
/// printed: the first overrides are a scene's printed values (Given); idle_sets: Given::idle_sets.
template <class Error, class Target>
Target loadKeys(const KeyTable<Target>& table, const std::string& yaml, const std::string& origin,
                const std::vector<std::string>& overrides, std::vector<std::string>* warnings = nullptr,
                std::size_t printed = 0, std::vector<std::pair<int, std::string>>* idle_sets = nullptr) {
  std::vector<std::pair<std::string, std::string>> names;
  for (const auto& k : table.keys) names.emplace_back(k.key, k.alternative);
  Given given(table.words, names, yaml, origin, overrides, table.aliases, printed);
  if (given.unreadable()) throw Error(given.problems);
  Target t{};
  for (const auto& k : table.keys) given.apply(k.key, [&](const YAML::Node& n) { k.set(t, n); });
  if (table.derive) table.derive(t, given);
  for (const auto& k : table.keys) {
    if (!k.refusal) continue;
    if (const std::string why = k.refusal(t); !why.empty()) given.refuse(k.key, why);
  }
  if (given.problems.empty() && table.validate) table.validate(t, given);
  if (!given.problems.empty()) throw Error(given.problems);
  if (warnings) *warnings = std::move(given.warnings);
  if (idle_sets) *idle_sets = std::move(given.idle_sets);
  return t;
}

/// Key listings: aligned columns, or the Markdown table of the READMEs.
std::string keysText(const std::vector<KeyInfo>& keys);
std::string keysMarkdown(const std::vector<KeyInfo>& keys);

// ---- building tables ----

/// Field accessor for the builders: member m of what part(target) returns.
template <class Part, class M>
auto field(Part part, M m) {
  return [part, m](auto& t) -> auto& { return part(t).*m; };
}
/// Member m of the target itself.
template <class M>
auto field(M m) {
  return [m](auto& t) -> auto& { return t.*m; };
}

/// Key builders for a Target; `f` is a field accessor (field() or a lambda
/// `[](auto& t) -> auto& { return ...; }`).
template <class Target>
struct Keys {
  using K = Key<Target>;

  template <class F, class Conv, class Show>
  static K bind(std::string key, std::string type, std::string unit, std::string meaning, F f, Conv conv,
                Show show, const Check& check) {
    K k(std::move(key), std::move(type), std::move(unit), check.rule, std::move(meaning));
    k.set = [f, conv](Target& t, const YAML::Node& n) { f(t) = conv(n); };
    k.get = [f, show](const Target& t) { return std::string(show(f(t))); };
    if (check.holds) {
      k.refusal = [f, show, check](const Target& t) -> std::string {
        const auto& v = f(t);
        return holds(check, v) ? std::string() : check.refusal() + ", got " + show(v);
      };
    }
    return k;
  }
  /// check on the components of a number, vector or matrix (other values have no check).
  template <class V>
  static bool holds(const Check& check, const V& v) {
    if constexpr (std::is_arithmetic_v<V>) {
      const double x = static_cast<double>(v);
      return check.holds(std::span<const double>(&x, 1));
    } else if constexpr (std::is_base_of_v<Eigen::MatrixBase<V>, V>) {
      return check.holds(std::span<const double>(v.data(), static_cast<std::size_t>(v.size())));
    } else {
      return true;
    }
  }
  template <class F>
  static K number(std::string key, std::string unit, std::string meaning, F f, const Check& c = {}) {
    return bind(std::move(key), "number", std::move(unit), std::move(meaning), f, asNumber, formatNumber, c);
  }
  template <class F>
  static K integer(std::string key, std::string unit, std::string meaning, F f, const Check& c = {}) {
    return bind(std::move(key), "int", std::move(unit), std::move(meaning), f, asInt,
                [](long long x) { return std::to_string(x); }, c);
  }
  template <int N, class F>
  static K vector(std::string key, std::string unit, std::string meaning, F f, const Check& c = {},
                  const char* expected = nullptr) {
    return bind(
        std::move(key), "vec" + std::to_string(N), std::move(unit), std::move(meaning), f,
        [expected](const YAML::Node& n) { return asVector<N>(n, expected); },
        [](const Eigen::Matrix<double, N, 1>& v) { return formatList({v.data(), static_cast<std::size_t>(N)}); },
        c);
  }
  template <class F>
  static K inertia(std::string key, std::string meaning, F f) {
    return bind(std::move(key), "inertia", "kg m^2", std::move(meaning), f, asInertia, formatInertia, bodyInertia());
  }
  template <class F>
  static K text(std::string key, std::string meaning, F f) {
    return bind(std::move(key), "string", "", std::move(meaning), f, asString,
                [](const std::string& s) { return s; }, Check{});
  }
  template <class E, class F>
  static K choice(std::string key, std::string meaning, F f, std::vector<std::pair<std::string, E>> names) {
    std::vector<std::string> words;
    for (const auto& nv : names) words.push_back(nv.first);
    return bind(
        std::move(key), join(words, "|"), "", std::move(meaning), f,
        [names, words](const YAML::Node& n) { return names[asChoice(n, words)].second; },
        [names](E e) {
          for (const auto& [name, value] : names) {
            if (value == e) return name;
          }
          return std::string("?");
        },
        Check{});
  }
};

/// Appends the keys of a part of Outer (part(outer) -> Inner&) under `prefix`.
template <class Outer, class Inner, class Part>
void embed(std::vector<Key<Outer>>& out, const std::string& prefix, const std::vector<Key<Inner>>& inner,
           Part part) {
  for (const Key<Inner>& k : inner) {
    Key<Outer> o(prefix + k.key, k.type, k.unit, k.check, k.meaning);
    o.set = [set = k.set, part](Outer& t, const YAML::Node& n) { set(part(t), n); };
    if (k.get) o.get = [get = k.get, part](const Outer& t) { return get(part(t)); };
    if (k.present) o.present = [present = k.present, part](const Outer& t) { return present(part(t)); };
    if (k.refusal) o.refusal = [r = k.refusal, part](const Outer& t) { return r(part(t)); };
    if (!k.alternative.empty()) o.alternative = prefix + k.alternative;
    out.push_back(std::move(o));
  }
}

}  // namespace gimbalsim
