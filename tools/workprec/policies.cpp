#include "policies.hpp"

#include <yaml-cpp/yaml.h>

#include <stdexcept>

#include "gimbalsim/input/key_registry.hpp"

namespace gimbalsim::workprec {

std::vector<Policy> loadPolicies(const std::string& path) {
  YAML::Node root;
  std::string text, why;
  Problem refused;
  if (!readFile(path, text, &why)) throw std::runtime_error(path + ": cannot open policy file: " + why);
  if (!loadDocument(text, path, root, refused)) throw std::runtime_error(refused.text);
  const YAML::Node list = root["policies"];
  if (!list || !list.IsSequence()) throw std::runtime_error(path + ": expected a list 'policies:'");
  std::vector<Policy> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node n = list[i];
    const std::string where = path + ":" + std::to_string(n.Mark().line + 1) + ": policy #" + std::to_string(i + 1);
    try {
      Policy p;
      for (const auto& kv : n) {
        const std::string k = kv.first.as<std::string>();
        if (k == "name") {
          p.name = kv.second.as<std::string>();
        } else if (k == "sets") {
          p.sets = kv.second.as<std::vector<std::string>>();
        } else if (k == "contact_only") {
          p.contact_only = kv.second.as<bool>();
        } else if (k == "sweep") {
          p.sweep_key = kv.second.as<std::string>();
        } else if (k == "values") {
          p.sweep_values = kv.second.as<std::vector<std::string>>();
        } else {
          throw std::runtime_error("unknown field '" + k + "'");
        }
      }
      if (p.name.empty()) throw std::runtime_error("needs a name");
      if (p.sweep_key.empty() != p.sweep_values.empty()) {
        throw std::runtime_error("'sweep' and 'values' go together");
      }
      for (const std::string& s : p.sets) {
        if (s.find('=') == std::string::npos) throw std::runtime_error("set '" + s + "' is not key=value");
      }
      out.push_back(std::move(p));
    } catch (const std::exception& e) {
      throw std::runtime_error(where + ": " + e.what());
    }
  }
  return out;
}

std::string expandSet(const std::string& set, double h) {
  const std::size_t at = set.find("{h}");
  if (at == std::string::npos) return set;
  double value = h;
  std::size_t end = at + 3;
  if (end < set.size() && set[end] == '*') {
    std::size_t used = 0;
    const std::string rest = set.substr(end + 1);
    value = h * std::stod(rest, &used);
    end += 1 + used;
  }
  return set.substr(0, at) + formatNumber(value) + set.substr(end);
}

}  // namespace gimbalsim::workprec
