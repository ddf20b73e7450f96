// The stress grid's CSV: see stress_csv.hpp.
#include "stress_csv.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <sstream>

#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/io/output_file.hpp"

namespace gimbalsim::stress {

std::string csvText(const std::vector<const Case*>& all) {
  std::ostringstream f;
  const std::string header =
      "group,scene,sets,verdict,reason,t_end_s,impacts,substeps,substeps_per_s,max_substeps_in_step,"
      "momentum_rel_linear,momentum_rel_angular,energy_rise_rel,energy_change_rel,energy_final_rel,"
      "max_penetration_m,penetration_limit_m,wall_s";
  const auto figures = std::count(header.begin(), header.end(), ',') - 4;  // the columns after "reason"
  f << header << "\n";
  const auto q = [](const std::string& s) { return io::csvTextCell(s); };  // the convention's text cell
  auto n = [](double x) {  // the CSV convention's numbers (io/csv_format.hpp)
    std::string s;
    io::appendCsvNumber(s, x);
    return s;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Case* c : all) {
    const Outcome& o = c->out;
    if (o.verdict == Verdict::Refused) {  // nothing ran: no figure, the reason says why (never a bare 0)
      f << q(c->group) << "," << q(c->scene) << "," << q(joined(c->sets)) << "," << verdictName(o.verdict) << ","
        << q(o.reason);
      for (long i = 0; i < figures; ++i) f << "," << n(nan);
      f << "\n";
      continue;
    }
    f << q(c->group) << "," << q(c->scene) << "," << q(joined(c->sets)) << "," << verdictName(o.verdict) << ","
      << q(o.reason) << "," << n(o.run.t_end) << "," << o.run.stats.impacts << "," << o.run.stats.substeps << ","
      << n(o.substeps_per_second) << "," << o.run.stats.max_substeps_in_step << "," << n(o.momentum_rel_linear)
      << "," << n(o.momentum_rel_angular) << "," << n(o.energy_rise_rel) << "," << n(o.energy_change_rel) << ","
      << n(o.energy_final_rel) << "," << n(o.max_penetration) << "," << n(o.penetration_limit) << ","
      << n(o.run.wall_seconds) << "\n";
  }
  return f.str();
}

void writeCsv(const std::string& path, const std::vector<const Case*>& all) {
  io::writeFileAtomically(path, csvText(all));
}

}  // namespace gimbalsim::stress
