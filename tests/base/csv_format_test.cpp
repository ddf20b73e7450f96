// The one CSV convention (io/csv_format.hpp): names with the unit as a
// suffix, identifiers numpy keeps as they are; numbers that read back as the
// same double, never -0; and every bench message's CSV header (the truth CSV,
// gimbalsim_log2csv's files) and the simulate CSV's header in it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/firmware_sim/csv_rows.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/run_output/run_output.hpp"

namespace gimbalsim::io {
namespace {

std::string number(double x) {
  char buf[32];
  return std::string(buf, static_cast<std::size_t>(formatCsvNumber(buf, x)));
}

TEST(CsvFormat, NamesCarryTheUnitAsASuffix) {
  EXPECT_EQ(csvName("t", "s"), "t_s");
  EXPECT_EQ(csvName("bore_x", "-"), "bore_x");
  EXPECT_EQ(csvName("dtheta1", "rad/s"), "dtheta1_rad_per_s");
  EXPECT_EQ(csvName("base_ax", "m/s^2"), "base_ax_m_per_s2");
  EXPECT_EQ(csvName("mom_lx", "N m s"), "mom_lx_Nms");
  EXPECT_EQ(csvNameOf("tau1[N m]"), "tau1_Nm");
  EXPECT_EQ(csvNameOf("seq[-]"), "seq");
  EXPECT_EQ(csvNameOf("plain"), "plain");
  EXPECT_EQ(csvName("azimuth_ki", "N m/(rad s)"), "azimuth_ki_Nm_per_rad_s");
}

TEST(CsvFormat, EveryKeyOfTheSceneAndTheControllerNamesAColumn) {
  // The sweep's and the tuner's tables name a column per dispersed key: key
  // with '.' -> '_', its unit a suffix. Each must be an identifier.
  const std::regex id("[A-Za-z_][A-Za-z0-9_]*");
  std::vector<KeyInfo> keys = firmware::plantTable().info();
  for (KeyInfo& k : controllers::controllerKeys()) keys.push_back(std::move(k));
  ASSERT_GT(keys.size(), 100u);
  for (const KeyInfo& k : keys) {
    std::string name = k.key;
    std::replace(name.begin(), name.end(), '.', '_');
    const std::string column = csvName(name, k.unit);
    EXPECT_TRUE(std::regex_match(column, id)) << k.key << " [" << k.unit << "] -> " << column;
  }
}

// kRowFields is Row, member by member and in order (rowData() and the CSV
// read the row as one array), with names that are unique.
TEST(CsvFormat, RowFieldsCoverRowMemberByMemberInOrder) {
  Row r{};
  std::set<std::string> names;
  for (int i = 0; i < kNumColumns; ++i) {
    EXPECT_EQ(&(r.*kRowFields[i].member), rowData(r) + i) << kRowFields[i].name;
    EXPECT_TRUE(names.insert(kRowFields[i].name).second) << "twice: " << kRowFields[i].name;
    EXPECT_STRNE(kRowFields[i].unit, "") << kRowFields[i].name;
    EXPECT_EQ(columnIndex(kRowFields[i].name), i);
  }
  EXPECT_EQ(columnIndex("no_such_column"), -1);
}

TEST(CsvFormat, NumbersRoundTripAndNeverMinusZero) {
  EXPECT_EQ(number(-0.0), "0");
  EXPECT_EQ(number(0.1), "0.1");
  for (double x : {0.1, -1.0 / 3.0, 1e-300, 6.02214076e23, 846.78181646028451, 5e-324}) {
    EXPECT_EQ(std::strtod(number(x).c_str(), nullptr), x) << number(x);
  }
}

TEST(CsvFormat, TextCellsNeedNoQuoting) {
  EXPECT_EQ(csvTextCell("plain text"), "plain text");
  EXPECT_EQ(csvTextCell("a, b \"c\" --set #1\nnext\r"), "a; b 'c' --set no. 1 next ");
}

/// Every cell of a header line is an identifier (what numpy's
/// genfromtxt(names=True) keeps unchanged), and no two are equal.
void expectIdentifiers(const std::string& header) {
  ASSERT_FALSE(header.empty());
  EXPECT_EQ(header.back(), '\n');
  std::stringstream ss(header.substr(0, header.size() - 1));
  std::string cell;
  std::set<std::string> seen;
  const std::regex id("[A-Za-z_][A-Za-z0-9_]*");
  while (std::getline(ss, cell, ',')) {
    EXPECT_TRUE(std::regex_match(cell, id)) << cell << " in " << header;
    EXPECT_TRUE(seen.insert(cell).second) << "repeated " << cell;
  }
}

TEST(CsvFormat, EveryHeaderTheProjectWritesIsIdentifiers) {
  using namespace gimbalsim::firmware::csv;
  expectIdentifiers(header<TruthFields>());
  expectIdentifiers(header<StatusFields>());
  expectIdentifiers(header<CommandFields>());
  expectIdentifiers(header<LoopStatsFields>());
  expectIdentifiers(header<AttitudeFields>());
  expectIdentifiers(header<AntennaFields>());
  using K = ClearanceKind;
  for (K k1 : {K::Ideal, K::Planar, K::Spatial}) {
    for (K k2 : {K::Ideal, K::Planar, K::Spatial}) {
      const std::string h = csvHeader(outputColumns(k1, k2));
      expectIdentifiers(h);
      EXPECT_EQ(h.rfind("t_s,base_x_m,", 0), 0u) << h;
    }
  }
}

/// The names of a header line, without units.
std::string headerTail(const std::string& h, const std::string& after) {
  const std::size_t at = h.find(after);
  return at == std::string::npos ? "(no " + after + ")" : h.substr(at + after.size());
}

TEST(CsvFormat, AScenesColumnsFollowItsJointKinds) {
  // The paper's kinds (an ideal joint 1) write the 42 columns they always
  // did; a clearance joint 1 adds its six, each spatial joint its five, in
  // this order after the energy.
  using K = ClearanceKind;
  for (K k2 : {K::Ideal, K::Planar}) {
    const std::string h = csvHeader(outputColumns(K::Ideal, k2));
    EXPECT_EQ(std::count(h.begin(), h.end(), ','), 41) << h;
    EXPECT_EQ(headerTail(h, ",mom_lz_Nms,"), "energy_J\n");
  }
  EXPECT_EQ(headerTail(csvHeader(outputColumns(K::Planar, K::Planar)), ",energy_J,"),
            "ecc1_x_m,ecc1_y_m,ecc1_m,delta1_m,fn1_N,ft1_N\n");
  EXPECT_EQ(headerTail(csvHeader(outputColumns(K::Ideal, K::Spatial)), ",energy_J,"),
            "tilt2_rad,delta2_minus_m,delta2_plus_m,fn2_minus_N,fn2_plus_N\n");
  EXPECT_EQ(headerTail(csvHeader(outputColumns(K::Spatial, K::Planar)), ",ft1_N,"),
            "tilt1_rad,delta1_minus_m,delta1_plus_m,fn1_minus_N,fn1_plus_N\n");
  const std::string both = csvHeader(outputColumns(K::Spatial, K::Spatial));
  EXPECT_EQ(std::count(both.begin(), both.end(), ','), 42 + 6 + 5 + 5 - 1) << both;
  // A row writes the same columns as its header.
  Row r{};
  r.tilt2 = 0.5;
  std::string line;
  appendCsvRow(line, r, outputColumns(K::Ideal, K::Spatial));
  EXPECT_EQ(std::count(line.begin(), line.end(), ','), 46) << line;
  const std::string tail = ",0,0.5,0,0,0,0\n";  // energy, then tilt2 .. fn2_plus
  EXPECT_EQ(line.substr(line.size() - tail.size()), tail) << line;
}

}  // namespace
}  // namespace gimbalsim::io
