// MovingAI benchmark maps and scenario lists (navctl plan --map M --scen S).
#include "services/common/movingai_format.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = navd::fuzz::Text(data, size);
  navd::fuzz::Refuses([&] { navd::ParseMovingAiMap(text, "fuzz.map"); });
  navd::fuzz::Refuses([&] { navd::ParseMovingAiScenarios(text, "fuzz.scen"); });
  return 0;
}
