// How values are written back (what --set reads back exactly) and the one
// whole-multiple rule for times given in steps.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gimbalsim {

using Mat3 = Eigen::Matrix3d;  // the same alias as the dynamics' (spatial.hpp)

std::string formatNumber(double x);                ///< shortest round trip (std::to_chars)
/// Rounded to `digits` significant figures (printf's %.<digits>g): for people,
/// and for values defined by their rounded spelling (the stress grid's).
std::string formatSignificant(double x, int digits);
std::string formatList(std::span<const double> v);  ///< "[a, b, c]"
std::string formatInertia(const Mat3& I);           ///< diagonal, 6-list or 3x3, as asInertia reads it
std::string join(const std::vector<std::string>& parts, const std::string& sep);
/// A character that splits or reorders a displayed line: U+0085, U+2028/9 and the bidi controls U+061C, U+200E/F,
/// U+202A..E, U+2066..9. Shown in a file, the line an editor displays is not the one a program reads.
bool isLayoutCodePoint(unsigned cp);
/// The length of the well-formed UTF-8 character at s[i] (1 for ASCII), its code point in *cp; 0 when the bytes
/// there are none (a stray continuation byte, an overlong form, a surrogate, a sequence cut short).
std::size_t utf8At(const std::string& s, std::size_t i, unsigned* cp);
/// A character no message prints raw, at s[i]: a control character but tab (C0, DEL, C1) or isLayoutCodePoint
/// (well-formed UTF-8 only): its code point, and its length in *bytes.
std::optional<unsigned> unprintableAt(const std::string& s, std::size_t i, std::size_t* bytes);
/// Text as a message may print it: each unprintableAt as <U+XXXX> (a tab too with tab_shown: a column's text),
/// each byte that is not UTF-8 as <0xHH>, every other character as given.
std::string shownText(const std::string& s, bool tab_shown = false);

/// The one rule for a time that must be whole steps (a duration, a row
/// interval, a control period): value / unit within a relative 1e-12 of a
/// whole number >= 1. The slack absorbs decimal spellings (0.3 / 0.1 is
/// 2.9999999999999996) and stays below one step up to RunBounds::kMaxSteps.
bool isWholeMultiple(double value, double unit);
/// "" when isWholeMultiple, else the problem, naming the unit and the nearest
/// valid values, e.g. "must be a whole multiple of sim.step (0.001 s): 0.002 or 0.003".
std::string wholeMultipleProblem(double value, double unit, const std::string& unit_name);

}  // namespace gimbalsim
