// Scenario files (navsim --scenario): a world plus people, doors, missions and faults.
#include "simulator/scenario.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = navd::fuzz::Text(data, size);
  navd::fuzz::Refuses([&] { navd::sim::ParseScenario(text, "fuzz.yaml", "/nonexistent"); });
  return 0;
}
