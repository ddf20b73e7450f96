// The truth message's columns that are also output columns (observables.hpp
// kRowFields), matched by name: the firmware copies them from the Row it
// observes each tick, so a column added to both lists reaches the truth
// without a third list. The rest of the truth (time stamps, attitude
// quaternion, torques, faults, the observer's target) the firmware fills itself.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>
#include <type_traits>

#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/dynamics/observables.hpp"

namespace gimbalsim::firmware {

/// A truth column's name without its unit: "ecc1_x[m]" -> "ecc1_x".
constexpr std::string_view columnName(std::string_view truth_column) {
  return truth_column.substr(0, truth_column.find('['));
}

/// The Truth doubles that copy a Row column: where each lies in Truth and
/// the Row member it copies.
struct TruthFromRow {
  struct Slot {
    std::size_t offset;  ///< bytes from the start of a contract::Truth to the double
    double Row::*member;
    int column;          ///< its index in kRowFields
  };
  std::array<Slot, kNumColumns> slots{};
  int count = 0;
};

/// Built on first use (the Firmware's constructor), from the two field lists.
inline const TruthFromRow& truthFromRow() {
  static const TruthFromRow table = [] {
    TruthFromRow t;
    contract::Truth probe;
    const auto* base = reinterpret_cast<const char*>(&probe);
    auto add = [&](std::string_view truth_column, const double& slot) {
      const int i = columnIndex(columnName(truth_column));
      if (i < 0) return;
      t.slots[t.count++] = {static_cast<std::size_t>(reinterpret_cast<const char*>(&slot) - base),
                            kRowFields[i].member, i};
    };
    contract::TruthFields::visit(
        [&](contract::Columns names, auto& field) {
          using T = std::remove_reference_t<decltype(field)>;
          if constexpr (std::is_same_v<T, double>) {
            add(*names.begin(), field);
          } else if constexpr (std::is_array_v<T> && std::is_same_v<std::remove_extent_t<T>, double>) {
            const char* const* name = names.begin();
            for (std::size_t j = 0; j < std::extent_v<T>; ++j) add(name[j], field[j]);
          }
        },
        probe);
    return t;
  }();
  return table;
}

/// Copies every Truth column that is a Row column. noexcept, no allocation.
inline void copyRowToTruth(const Row& row, contract::Truth& truth) noexcept {
  const TruthFromRow& t = truthFromRow();
  auto* base = reinterpret_cast<char*>(&truth);
  for (int k = 0; k < t.count; ++k) {
    *reinterpret_cast<double*>(base + t.slots[k].offset) = row.*(t.slots[k].member);
  }
}

}  // namespace gimbalsim::firmware
