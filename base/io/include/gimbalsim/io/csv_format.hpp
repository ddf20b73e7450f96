// The one CSV convention of every CSV the project writes (docs/usage.md
// "CSV files"): a header of names that numpy's genfromtxt(names=True),
// pandas, the csv module and PlotJuggler all read unchanged (letters, digits
// and '_', the unit as a suffix: t_s, theta1_rad, dtheta1_rad_per_s, bore_x
// for a unitless value), and numbers in the shortest form that reads back as
// the same double (std::to_chars), never "-0"; text cells unquoted, with
// nothing a reader would take for a separator, a quote or a comment.
#pragma once

#include <string>
#include <string_view>

namespace gimbalsim::io {

/// `name` with `unit` as its suffix: "" or "-" adds nothing; '/' reads
/// "_per_", spaces and '^' are dropped ("rad/s^2" -> "rad_per_s2", "N m" -> "Nm"),
/// parentheses too, a space inside them reads '_' ("N m/(rad s)" -> "Nm_per_rad_s");
/// any other character becomes '_'.
std::string csvName(std::string_view name, std::string_view unit);

/// "name[unit]" (the message field lists' spelling) as csvName(name, unit);
/// a cell without brackets is returned as it is.
std::string csvNameOf(std::string_view bracketed);

/// Writes x into buf (at least 32 bytes) as the convention says; returns
/// the length. No allocation, no exception (the real-time writers use it).
int formatCsvNumber(char* buf, double x) noexcept;

/// Appends formatCsvNumber(x) to out.
void appendCsvNumber(std::string& out, double x);

/// `text` as a CSV cell that every reader splits alike without quoting
/// (numpy's genfromtxt reads no quotes and takes '#' for a comment):
/// ',' reads ';', '"' reads '\'', '#' reads "no. ", a line break a space.
std::string csvTextCell(std::string_view text);

}  // namespace gimbalsim::io
