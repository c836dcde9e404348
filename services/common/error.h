#pragma once
// navd's error type for algorithm code. Services throw navd::Error with a code and a message that
// names the offending field; the gRPC adapters map the code to a status, so algorithms never see
// transport types.
#include <stdexcept>
#include <string>

namespace navd {

enum class ErrorCode {
  kInvalidArgument,
  kNotFound,
  kFailedPrecondition,
  kDeadlineExceeded,
  kCancelled,
  kUnavailable,
  kInternal,
};

class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ErrorCode code() const { return code_; }

 private:
  ErrorCode code_;
};

const char* ErrorCodeName(ErrorCode code);

}  // namespace navd
