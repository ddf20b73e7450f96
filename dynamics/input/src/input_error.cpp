#include "gimbalsim/input/input_error.hpp"

#include <utility>

namespace gimbalsim {

namespace {
std::string joined(const std::vector<Problem>& problems) {
  std::string all;
  for (const auto& p : problems) all += (all.empty() ? "" : "\n") + p.text;
  return all;
}

std::vector<Problem> fromTexts(const std::vector<std::string>& texts) {
  std::vector<Problem> out;
  for (const std::string& t : texts) {
    Problem p;
    p.text = t;
    out.push_back(p);
  }
  return out;
}
}  // namespace

InputError::InputError(std::vector<Problem> problems)
    : std::runtime_error(joined(problems)), details_(std::move(problems)) {
  for (const auto& p : details_) texts_.push_back(p.text);
}

InputError::InputError(const std::vector<std::string>& texts) : InputError(fromTexts(texts)) {}

InputError::InputError(const std::string& problem) : InputError(std::vector<std::string>{problem}) {}

}  // namespace gimbalsim
