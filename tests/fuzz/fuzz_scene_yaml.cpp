// libFuzzer target: scene file text through the scene loader (the prescan,
// yaml-cpp, every key's conversion and check, validate(), Model::finalize()).
// Loaded or refused with places; never a crash, an escaped exception, or
// more time or memory than -timeout / -rss_limit_mb allow (tools/ci/fuzz.sh).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.hpp"
#include "gimbalsim/scene/scene.hpp"

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) { return gimbalsim::fuzz::withBounds(argc, argv); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > static_cast<std::size_t>(gimbalsim::InputBounds::kMaxFileBytes)) return -1;  // readFile refuses it
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)gimbalsim::loadSceneText(text, "fuzz.yaml", {});
  } catch (const gimbalsim::SceneError& e) {
    gimbalsim::fuzz::checkRefusal(e, "fuzz.yaml");
  }
  return 0;
}
