// libFuzzer target: `--set` arguments (one per input line) over an empty
// scene: the key=value split, the prescan of the value, the conversion and
// every check. Refused with the --set index, or loaded; nothing else.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_check.hpp"
#include "gimbalsim/scene/scene.hpp"

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) { return gimbalsim::fuzz::withBounds(argc, argv); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> sets;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t nl = text.find('\n', start);
    sets.push_back(text.substr(start, nl == std::string::npos ? std::string::npos : nl - start));
    if (nl == std::string::npos) break;
    start = nl + 1;
  }
  try {
    (void)gimbalsim::loadSceneText("", "fuzz.yaml", sets);
  } catch (const gimbalsim::SceneError& e) {
    gimbalsim::fuzz::checkRefusal(e, "fuzz.yaml");
  }
  return 0;
}
