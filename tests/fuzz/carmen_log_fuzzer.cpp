// CARMEN laser logs (navd-replay --log, navctl replay --log), lenient and strict.
#include "services/common/carmen_log.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = navd::fuzz::Text(data, size);
  navd::fuzz::Refuses([&] { navd::ParseCarmenLog(text, "fuzz.log", false); });
  navd::fuzz::Refuses([&] { navd::ParseCarmenLog(text, "fuzz.log", true); });
  return 0;
}
