// The key listings (`gimbalsim keys`, the key docs): aligned text and Markdown.
#include "gimbalsim/input/key_registry.hpp"

#include <algorithm>

namespace gimbalsim {

namespace {
std::vector<std::vector<std::string>> rows(const std::vector<KeyInfo>& keys) {
  std::vector<std::vector<std::string>> out = {{"key", "type", "unit", "default", "check", "meaning"}};
  for (const KeyInfo& k : keys) out.push_back({k.key, k.type, k.unit, k.default_value, k.check, k.meaning});
  return out;
}
}  // namespace

std::string keysText(const std::vector<KeyInfo>& keys) {
  // Each column as wide as its longest cell, so that every row's cells start
  // at the same place (a cap let a 30-character type push the rest of its row).
  const auto table = rows(keys);
  std::vector<std::size_t> width(table[0].size(), 0);
  for (const auto& row : table) {
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  std::string out;
  for (const auto& row : table) {
    std::string line;
    for (std::size_t c = 0; c + 1 < row.size(); ++c) line += row[c] + std::string(width[c] - row[c].size() + 2, ' ');
    out += line + row.back() + "\n";
  }
  return out;
}

std::string keysMarkdown(const std::vector<KeyInfo>& keys) {
  auto cell = [](const std::string& s) {
    std::string e;
    for (char ch : s) e += ch == '|' ? std::string("\\|") : std::string(1, ch);
    return e;
  };
  auto code = [&](const std::string& s) {
    std::string c;
    if (!s.empty()) c.append("`").append(cell(s)).append("`");
    return c;
  };
  const auto table = rows(keys);
  std::string out = "| " + join(table[0], " | ") + " |\n|---|---|---|---|---|---|\n";
  for (std::size_t r = 1; r < table.size(); ++r) {
    const auto& k = table[r];
    out += "| " + join({code(k[0]), cell(k[1]), cell(k[2]), code(k[3]), cell(k[4]), cell(k[5])}, " | ") + " |\n";
  }
  return out;
}

}  // namespace gimbalsim
