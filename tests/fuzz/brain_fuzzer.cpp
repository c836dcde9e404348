// Brain files (navd --brain): the utility functions' parameters.
#include "services/navigation/utility_decision_maker.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = navd::fuzz::Text(data, size);
  navd::fuzz::Refuses([&] { navd::navigation::ParseBrain(text, "fuzz.yaml"); });
  return 0;
}
