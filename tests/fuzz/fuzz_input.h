#pragma once
// What every harness shares: the fuzzer's bytes as text, and the rule they all check. A parser of
// outside input may refuse it only with navd::Error (the one readable line users see); any other
// exception escaping, a crash, a leak or undefined behaviour is a bug the fuzzer reports.
#include <cstddef>
#include <cstdint>
#include <string>

#include "services/common/error.h"

namespace navd::fuzz {

inline std::string Text(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Runs `parse`, accepting navd::Error as the answer to bad input.
template <typename Parse>
void Refuses(Parse&& parse) {
  try {
    parse();
  } catch (const navd::Error&) {
  }
}

}  // namespace navd::fuzz
