// libFuzzer target: controller configuration text through its loader (the
// same key registry as scenes, the controller's own keys and validate()).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.hpp"
#include "gimbalsim/controllers/config.hpp"

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) { return gimbalsim::fuzz::withBounds(argc, argv); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > static_cast<std::size_t>(gimbalsim::InputBounds::kMaxFileBytes)) return -1;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)gimbalsim::controllers::loadControllerConfigText(text, "fuzz.yaml", {});
  } catch (const gimbalsim::controllers::ConfigError& e) {
    gimbalsim::fuzz::checkRefusal(e, "fuzz.yaml");
  }
  return 0;
}
