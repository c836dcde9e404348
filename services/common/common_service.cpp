#include "services/common/common_service.h"

#include <chrono>
#include <cmath>

namespace navd {

grpc::Status ToGrpcStatus(const Error& e) {
  grpc::StatusCode code = grpc::StatusCode::INTERNAL;
  switch (e.code()) {
    case ErrorCode::kInvalidArgument: code = grpc::StatusCode::INVALID_ARGUMENT; break;
    case ErrorCode::kNotFound: code = grpc::StatusCode::NOT_FOUND; break;
    case ErrorCode::kFailedPrecondition: code = grpc::StatusCode::FAILED_PRECONDITION; break;
    case ErrorCode::kDeadlineExceeded: code = grpc::StatusCode::DEADLINE_EXCEEDED; break;
    case ErrorCode::kCancelled: code = grpc::StatusCode::CANCELLED; break;
    case ErrorCode::kUnavailable: code = grpc::StatusCode::UNAVAILABLE; break;
    case ErrorCode::kInternal: code = grpc::StatusCode::INTERNAL; break;
  }
  return grpc::Status(code, e.what());
}

grpc::Status GuardedCall(const std::function<void()>& body) {
  try {
    body();
    return grpc::Status::OK;
  } catch (const Error& e) {
    return ToGrpcStatus(e);
  } catch (const std::exception& e) {
    return grpc::Status(grpc::StatusCode::INTERNAL, std::string("internal error: ") + e.what());
  }
}

void ToProto(double seconds, v1::Stamp* out) {
  const double s = std::floor(seconds);
  out->set_sec(static_cast<int64_t>(s));
  out->set_nanosec(static_cast<uint32_t>(std::min(999'999'999.0, (seconds - s) * 1e9)));
}

std::function<bool()> StopWhenDone(const grpc::ServerContextBase* context) {
  return [context] { return context->IsCancelled() || context->deadline() < std::chrono::system_clock::now(); };
}

}  // namespace navd
