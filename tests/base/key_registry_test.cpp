// The key registry (key_registry.hpp): every scene and controller key is
// documented, every default is valid, printed values load back, and the key
// tables in docs/scene_keys.md and docs/controller_keys.md are the ones the
// programs print (`gimbalsim keys --markdown`, `pointing_controller --keys
// --markdown`; tools/pages/gen_key_docs.py writes them there).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/scene/scene.hpp"
#include "gimbalsim/pointing/profile_keys.hpp"

namespace gimbalsim {
namespace {

const std::string kScenes = GIMBALSIM_SCENES_DIR;
const std::string kSource = GIMBALSIM_SOURCE_DIR;

/// The message with which load() refuses (an InputError: scene, configuration or profile), or "(accepted)".
template <class Load>
std::string refusalOf(Load load) {
  try {
    load();
    return "(accepted)";
  } catch (const InputError& e) {
    return e.what();
  }
}

std::string refusal(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  return refusalOf([&] { loadSceneText(yaml, "t.yaml", sets); });
}

void expectDocumented(const std::vector<KeyInfo>& keys) {
  const std::set<std::string> numeric = {"number", "int", "vec2", "vec3", "inertia"};
  std::set<std::string> seen;
  for (const KeyInfo& k : keys) {
    EXPECT_TRUE(seen.insert(k.key).second) << "twice: " << k.key;
    EXPECT_FALSE(k.type.empty()) << k.key;
    EXPECT_FALSE(k.meaning.empty()) << k.key;
    if (numeric.count(k.type)) {
      EXPECT_FALSE(k.unit.empty()) << "numeric key without a unit: " << k.key;
    }
  }
}

TEST(KeyRegistry, EveryKeyIsDocumented) {
  expectDocumented(firmware::plantTable().info());
  expectDocumented(controllers::controllerKeys());
  EXPECT_EQ(sceneKeys().size(), sceneTable().keys.size());
}

/// Every cell of `keysText` starts where its column's header does.
void expectAlignedColumns(const std::vector<KeyInfo>& keys) {
  const std::string text = keysText(keys);
  std::vector<std::string> lines;
  for (std::size_t a = 0, b; (b = text.find('\n', a)) != std::string::npos; a = b + 1) lines.push_back(text.substr(a, b - a));
  ASSERT_EQ(lines.size(), keys.size() + 1);
  std::vector<std::size_t> at;
  for (const char* h : {"key", "type", "unit", "default", "check", "meaning"}) at.push_back(lines[0].find(h));
  for (std::size_t r = 0; r < keys.size(); ++r) {
    const KeyInfo& k = keys[r];
    const std::string cells[] = {k.key, k.type, k.unit, k.default_value, k.check, k.meaning};
    for (std::size_t c = 0; c < 6; ++c) {
      EXPECT_EQ(lines[r + 1].substr(std::min(at[c], lines[r + 1].size()), cells[c].size()), cells[c])
          << k.key << ": column " << c << " does not start under its header";
    }
  }
}

TEST(KeyRegistry, KeyListingsKeepTheirColumnsWhateverACellsLength) {
  expectAlignedColumns(sceneKeys());
  expectAlignedColumns(controllers::controllerKeys());  // a 30-character type: none|clamping|back_calculation
  expectAlignedColumns({{"a", std::string(40, 't'), "m", "in (0, 1]", "1", "long type"}, {"b", "number", "", "", "", "x"}});
}

TEST(KeyRegistry, EmptySceneLoadsToTheDefaults) {
  const Scene loaded = loadSceneText("", "empty.yaml");
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_EQ(loaded.model.name, "empty.yaml");  // the one default not from Scene{}: the file name
  std::vector<std::string> got = sceneTable().values(loaded), want = sceneTable().values(Scene{});
  ASSERT_EQ(got.size(), want.size());
  ASSERT_EQ(got[0], "name=empty.yaml");
  ASSERT_EQ(want[0], "name=");
  got.erase(got.begin());
  want.erase(want.begin());
  EXPECT_EQ(got, want);
}

TEST(KeyRegistry, EmptyControllerConfigLoadsToTheDefaults) {
  const controllers::ControllerConfig c = controllers::loadControllerConfigText("", "empty.yaml");
  EXPECT_EQ(controllers::configValues(c), controllers::configValues(controllers::ControllerConfig{}));
  EXPECT_EQ(controllers::configValues(c).size(), controllers::controllerKeys().size());
}

TEST(KeyRegistry, PrintedSceneValuesLoadBack) {
  const firmware::PlantScene a = firmware::loadPlantScene(
      kScenes + "/paper_clearance.yaml",
      {"shaft2.inertia=[0.5, 5, 5, 0.1, 0, 0]", "contact.clearance=1e-4", "sensors.seed=7"});
  const std::vector<std::string> values = firmware::plantTable().values(a);
  const firmware::PlantScene b = firmware::loadPlantSceneText("", "printed", values);
  EXPECT_EQ(firmware::plantTable().values(b), values);
  EXPECT_EQ(b.scene.model.shaft2.inertia, a.scene.model.shaft2.inertia);
  EXPECT_EQ(b.scene.model.bearing[1].journal_radius, a.scene.model.bearing[1].journal_radius);
  EXPECT_EQ(b.sensors.seed, 7);
}

TEST(KeyRegistry, AKeyForBothJointsStillActsOnPrintedValues) {
  // A scene travels as its printed values (a pickled scene, a sweep's
  // workers): a joint's own key is printed only where it is its own, so an
  // override of the key for both joints acts on every joint that has none.
  const Scene a = loadScene(kScenes + "/paper_both_planar.yaml", {"joint1.contact.clearance=2e-4", "initial.ecc2=[1e-4, 0]"});
  const std::vector<std::string> printed = sceneTable().values(a);
  EXPECT_EQ(std::count_if(printed.begin(), printed.end(), [](const std::string& v) { return v.rfind("joint2.", 0) == 0; }),
            0);
  std::vector<std::string> again = printed;
  again.insert(again.end(), {"contact.clearance=3e-4", "friction.mu=0.3", "initial.ecc=[0, -5e-5]"});
  const Scene b = loadSceneText("", "printed", again, printed.size());
  EXPECT_NEAR(b.model.bearing[0].clearance, 2e-4, 1e-15) << "joint 1's own stays";
  EXPECT_NEAR(b.model.bearing[1].clearance, 3e-4, 1e-15) << "the override acts on joint 2";
  EXPECT_EQ(b.model.bearing[0].mu, 0.3);
  EXPECT_EQ(b.model.bearing[1].mu, 0.3);
  EXPECT_EQ(b.run.initial.ecc[0], Vec2(0, -5e-5));
  EXPECT_EQ(b.run.initial.ecc[1], Vec2(1e-4, 0)) << "joint 2's own stays";
  // Read back without overrides it is the same scene.
  const Scene c = loadSceneText("", "printed", printed);
  for (int j = 0; j < 2; ++j) {
    EXPECT_EQ(c.model.bearing[j].journal_radius, a.model.bearing[j].journal_radius) << j;
    EXPECT_EQ(c.run.initial.ecc[j], a.run.initial.ecc[j]) << j;
  }
}

TEST(KeyRegistry, ChecksAndValuesInWords) {
  EXPECT_EQ(greater(0).rule, "> 0");
  EXPECT_EQ(atLeast(1).rule, ">= 1");
  EXPECT_EQ(interval('(', 0, 1, ']').rule, "in (0, 1]");
  EXPECT_EQ(interval('[', 0, 0.5, ')').rule, "in [0, 0.5)");
  EXPECT_EQ(formatNumber(1e-3), "0.001");
  EXPECT_EQ(formatNumber(0.1 + 0.2), "0.30000000000000004");  // shortest that reads back exactly
  EXPECT_EQ(std::stod(formatNumber(5.992112452678286e-6)), 5.992112452678286e-6);
}

TEST(KeyRegistry, ClearanceDoesNotDependOnTheTablesOrder) {
  // contact.clearance stands for journal_radius = bearing_radius - c, with
  // the bearing radius given, whichever of the two keys the table sets first.
  KeyTable<Scene> first = sceneTable(), last = sceneTable();
  auto at = [](KeyTable<Scene>& t) {
    return std::find_if(t.keys.begin(), t.keys.end(), [](const auto& k) { return k.key == "contact.clearance"; });
  };
  std::rotate(first.keys.begin(), at(first), at(first) + 1);  // contact.clearance set before every other key
  std::rotate(at(last), at(last) + 1, last.keys.end());       // and after every other key
  ASSERT_EQ(first.keys.front().key, "contact.clearance");
  ASSERT_EQ(last.keys.back().key, "contact.clearance");
  const std::string yaml = "structure: {joint2: clearance}\ncontact: {clearance: 2.0e-4, bearing_radius: 0.03}\n";
  for (const KeyTable<Scene>* t : std::initializer_list<const KeyTable<Scene>*>{&first, &last, &sceneTable()}) {
    const Scene s = loadKeys<SceneError>(*t, yaml, "t.yaml", {});
    EXPECT_EQ(s.model.bearing[1].journal_radius, 0.03 - 2.0e-4);
  }
}

TEST(KeyRegistry, AlternativeKeysAndDefaultPlaces) {
  const std::string good = "structure: {joint2: clearance}\n";
  // Both radius forms in one file: refused, at the later one.
  EXPECT_NE(refusal(good + "contact: {journal_radius: 9e-3, clearance: 1e-3}\n")
                .find("t.yaml:2:33: key 'contact.clearance': give it or 'contact.journal_radius', not both"),
            std::string::npos);
  // A --set of one form replaces the other given in the file.
  const Scene s = loadSceneText(good + "contact: {journal_radius: 9e-3}\n", "t.yaml", {"contact.clearance=1e-3"});
  EXPECT_NEAR(s.model.bearing[1].clearance, 1e-3, 1e-15);
  // Both forms among the --set values: the later one was taken while the summary listed both (pass 71).
  EXPECT_NE(refusal(good, {"contact.clearance=1e-4", "contact.journal_radius=9.5e-3"})
                .find("--set #2 'contact.journal_radius=9.5e-3': key 'contact.journal_radius': sets the same field "
                      "as 'contact.clearance', given before it: give one of them"),
            std::string::npos);
  // The same key twice: the later value (usage.md).
  const Scene twice = loadSceneText(good, "t.yaml", {"contact.clearance=1e-4", "contact.clearance=2e-4"});
  EXPECT_NEAR(twice.model.bearing[1].clearance, 2e-4, 1e-15);
  // A derived journal radius is refused under the key that was given.
  EXPECT_NE(refusal(good, {"contact.clearance=0.02"})
                .find("--set #1 'contact.clearance=0.02': key 'contact.clearance': journal radius (the bearing radius "
                      "less any clearance given) must be > 0, got -0.01"),
            std::string::npos);
  // A default that a given key makes wrong is named as a default.
  EXPECT_NE(refusal(good, {"sim.step=1e-5"})
                .find("t.yaml: (default of sim.substep): key 'sim.substep': must be in (0, sim.step]"),
            std::string::npos);
}

TEST(KeyRegistry, ProfileSectionAloneIsTheControllersProfile) {
  const std::string file = std::string(GIMBALSIM_SOURCE_DIR) + "/controllers/config/default.yaml";
  const KeyTable<pointing::TargetProfile>& keys = pointing::profileKeys();
  EXPECT_EQ(keys.values(pointing::loadTargetProfile(file)),
            keys.values(controllers::loadControllerConfig(file).profile));
  // Other sections are not read; the profile's keys are checked as the controller checks them.
  EXPECT_NO_THROW(pointing::loadTargetProfileText("azimuth: {kp: -1}\nbogus: 1\nprofile: {}\n", "t.yaml"));
  // A file without the section (a scene) is refused, naming the file and the key.
  const std::string none = refusalOf([] { pointing::loadTargetProfileText("contact: {clearance: 1e-4}\n", "s.yaml"); });
  EXPECT_NE(none.find("s.yaml: key 'profile': missing"), std::string::npos) << none;
  const std::string what =
      refusalOf([] { pointing::loadTargetProfileText("profile: {slew_time: 0, slew_tim: 1}\n", "t.yaml"); });
  EXPECT_NE(what.find("t.yaml:1:11: key 'profile.slew_time': must be in [1e-06, 1e+09], got 0"), std::string::npos) << what;
  EXPECT_NE(what.find("t.yaml:1:25: unknown key 'profile.slew_tim'"), std::string::npos) << what;
}

/// Cells of a Markdown table row: split at unescaped '|', trimmed, `\|` and code quotes undone.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cur;
  for (std::size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '\\' && i + 1 < row.size() && row[i + 1] == '|') {
      cur += '|';
      ++i;
    } else if (row[i] == '|') {
      const auto b = cur.find_first_not_of(' '), e = cur.find_last_not_of(' ');
      cur = b == std::string::npos ? "" : cur.substr(b, e - b + 1);
      if (cur.size() >= 2 && cur.front() == '`' && cur.back() == '`') cur = cur.substr(1, cur.size() - 2);
      out.push_back(cur);
      cur.clear();
    } else {
      cur += row[i];
    }
  }
  return out;
}

/// The rows of the key table in a Markdown file, and the text before it.
std::vector<std::vector<std::string>> keyTable(const std::string& path, std::string& before) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::vector<std::vector<std::string>> rows;
  std::string line;
  bool in_table = false;
  while (std::getline(in, line)) {
    if (!in_table) {
      in_table = line == "| key | type | unit | default | check | meaning |";
      if (!in_table) before += line + "\n";
      continue;
    }
    if (line.rfind("|---", 0) == 0) continue;
    if (line.empty() || line[0] != '|') break;
    rows.push_back(cells(line));
  }
  return rows;
}

void expectDocTable(const std::string& path, const std::vector<KeyInfo>& keys, const std::string& command) {
  const std::string regenerate = ": regenerate the table with /usr/bin/python3 tools/pages/gen_key_docs.py (it runs " +
                                 command + ")";
  std::string before;
  const auto rows = keyTable(path, before);
  EXPECT_NE(before.find(command), std::string::npos) << path << " must name the command that prints its table";
  ASSERT_EQ(rows.size(), keys.size()) << path << regenerate;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const KeyInfo& k = keys[i];
    EXPECT_EQ(rows[i], (std::vector<std::string>{k.key, k.type, k.unit, k.default_value, k.check, k.meaning}))
        << path << " row " << i + 1 << regenerate;
  }
}

TEST(KeyRegistry, KeyDocsAreTheRegistry) {
  expectDocTable(kSource + "/docs/scene_keys.md", firmware::plantTable().info(), "gimbalsim keys --markdown");
  expectDocTable(kSource + "/docs/controller_keys.md", controllers::controllerKeys(),
                 "pointing_controller --keys --markdown");
}

TEST(KeyRegistry, EveryOldSpellingIsAKeyAndIsListedInTheDocs) {
  std::ifstream in(kSource + "/docs/scene_keys.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::set<std::string> names;
  for (const KeyInfo& k : firmware::plantTable().info()) names.insert(k.key);
  ASSERT_FALSE(sceneTable().aliases.empty());
  EXPECT_EQ(firmware::plantTable().aliases, sceneTable().aliases) << "the plant reads the scene's old spellings";
  for (const auto& [alias, key] : sceneTable().aliases) {
    EXPECT_TRUE(names.count(key)) << alias << " stands for " << key << ", which is not a key";
    EXPECT_FALSE(names.count(alias)) << alias << " is a key of its own";
    // The doc lists each old prefix with its key's: "| `contact1.*` ... | `joint1.contact.*` |".
    const std::string old_prefix = "`" + alias.substr(0, alias.find('.')) + ".*`";
    const std::string new_prefix = "`" + key.substr(0, key.rfind('.')) + ".*`";
    const auto row = doc.find("| " + old_prefix);
    ASSERT_NE(row, std::string::npos) << old_prefix << " is not listed in docs/scene_keys.md";
    EXPECT_NE(doc.substr(row, doc.find('\n', row) - row).find(new_prefix), std::string::npos)
        << old_prefix << " must be listed with " << new_prefix;
  }
}

}  // namespace
}  // namespace gimbalsim
