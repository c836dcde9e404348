// map_server maps (navd --map, LoadMap): the YAML's fields, and the PGM image in each mode.
#include "services/common/map_server_format.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = navd::fuzz::Text(data, size);
  std::string image;
  navd::fuzz::Refuses([&] { navd::ParseMapServerYaml(text, "fuzz.yaml", &image); });
  for (const char* mode : {"trinary", "scale", "raw"}) {
    navd::MapServerParams params;
    params.mode = mode;
    navd::fuzz::Refuses([&] { navd::DecodeMapServerImage(text, params, "fuzz.pgm"); });
  }
  return 0;
}
