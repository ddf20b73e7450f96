// The one reading of a number given as text (a flag, a cell of a file this
// project wrote): a plain finite decimal, nothing else. strtod alone also
// takes hex ("0x1p-3"), leading blanks, "inf" and "nan", which no writer of
// ours writes and no user means. Header-only: the fuzz targets' readers use it.
#pragma once

#include <cmath>
#include <cstdlib>
#include <string>

#include "gimbalsim/input/underflow.hpp"

namespace gimbalsim {

enum class DecimalProblem { None, Empty, NotDecimal, NotFinite, Underflow };

/// True when `text`, after an optional sign, starts with a 0 and another
/// digit ("010", "+00.5"): no writer of ours writes one, and CLI11 reads a
/// whole "010" as octal 8. Whole and real flags refuse it alike.
inline bool hasLeadingZero(const std::string& text) {
  const std::size_t i = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
  return text.size() > i + 1 && text[i] == '0' && text[i + 1] >= '0' && text[i + 1] <= '9';
}

/// Reads `text` into x; None when it is a plain finite decimal whose value
/// the parse kept (1e-400 would read as 0: Underflow).
inline DecimalProblem readPlainDecimal(const std::string& text, double& x) {
  if (text.empty()) return DecimalProblem::Empty;
  if (text.find_first_not_of("0123456789+-.eE") != std::string::npos) return DecimalProblem::NotDecimal;
  char* end = nullptr;
  x = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return DecimalProblem::NotDecimal;
  if (!std::isfinite(x)) return DecimalProblem::NotFinite;
  if (underflowed(text, x)) return DecimalProblem::Underflow;
  return DecimalProblem::None;
}

}  // namespace gimbalsim
