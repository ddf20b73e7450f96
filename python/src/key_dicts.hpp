// Key listings and key=value lists as Python objects, for scenes and
// controller configurations alike.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "gimbalsim/input/key_registry.hpp"

namespace gimbalsim::py {

/// [{key, type, unit, check, default, meaning}, ...]
inline pybind11::list keyInfoList(const std::vector<KeyInfo>& keys) {
  pybind11::list out;
  for (const KeyInfo& k : keys) {
    pybind11::dict d;
    d["key"] = k.key;
    d["type"] = k.type;
    d["unit"] = k.unit;
    d["check"] = k.check;
    d["default"] = k.default_value;
    d["meaning"] = k.meaning;
    out.append(d);
  }
  return out;
}

/// {"key": "value as --set reads it", ...} from "key=value" strings.
inline pybind11::dict keyValueDict(const std::vector<std::string>& key_values) {
  pybind11::dict d;
  for (const std::string& kv : key_values) {
    const auto eq = kv.find('=');
    d[pybind11::str(kv.substr(0, eq))] = kv.substr(eq + 1);
  }
  return d;
}

}  // namespace gimbalsim::py
