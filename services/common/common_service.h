#pragma once
// Edge helpers shared by the <area>_service gRPC adapters: proto <-> common types, and navd::Error
// -> grpc::Status. Adapter code only; algorithm code never includes this.
#include <grpcpp/grpcpp.h>

#include <functional>

#include "navd/v1/common.pb.h"
#include "services/common/error.h"
#include "services/common/pose2.h"

namespace navd {

grpc::Status ToGrpcStatus(const Error& e);

// Runs `body`, turning navd::Error into its status and anything else into INTERNAL.
grpc::Status GuardedCall(const std::function<void()>& body);

inline Pose2 FromProto(const v1::Pose2D& p) { return {p.x(), p.y(), p.theta()}; }
inline Point2 FromProto(const v1::Point2D& p) { return {p.x(), p.y()}; }
inline void ToProto(const Pose2& p, v1::Pose2D* out) {
  out->set_x(p.x);
  out->set_y(p.y);
  out->set_theta(p.theta);
}
inline void ToProto(const Point2& p, v1::Point2D* out) {
  out->set_x(p.x());
  out->set_y(p.y());
}
void ToProto(double seconds, v1::Stamp* out);

// A planner stop condition for a call: true once the client cancels or the deadline passes.
std::function<bool()> StopWhenDone(const grpc::ServerContextBase* context);

}  // namespace navd
