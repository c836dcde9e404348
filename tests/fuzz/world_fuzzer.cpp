// World files (navd --world, navsim --world). Map files named inside resolve against an empty
// folder, so only the YAML itself is fuzzed.
#include "services/common/world.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = navd::fuzz::Text(data, size);
  navd::fuzz::Refuses([&] { navd::ParseWorld(text, "fuzz.yaml", "/nonexistent"); });
  return 0;
}
