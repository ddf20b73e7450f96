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

std::vector<std::string> relabelledProblems(const InputError& e, const std::vector<std::string>& labels) {
  std::vector<std::string> out;
  for (const Problem& p : e.details()) {
    std::string text = p.text;
    const std::size_t k = static_cast<std::size_t>(p.set_index);
    const std::size_t end = text.find("': ");
    if (k >= 1 && k <= labels.size() && !labels[k - 1].empty() && text.rfind("--set #", 0) == 0 &&
        end != std::string::npos) {
      text = labels[k - 1] + text.substr(end + 1);
    }
    out.push_back(std::move(text));
  }
  if (e.details().empty()) out = e.problems();
  return out;
}

}  // namespace gimbalsim
