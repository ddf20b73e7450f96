// The stress grid's CSV: one row per run (verdict, reason, measured checks).
#pragma once

#include <string>
#include <vector>

#include "stress_grid.hpp"

namespace gimbalsim::stress {

/// The CSV text of these runs, header first.
std::string csvText(const std::vector<const Case*>& all);

/// Writes csvText atomically to path, creating its directory; throws
/// io::OutputError naming the file (or std::filesystem_error for the directory).
void writeCsv(const std::string& path, const std::vector<const Case*>& all);

}  // namespace gimbalsim::stress
