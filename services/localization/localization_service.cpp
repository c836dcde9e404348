#include "services/localization/localization_service.h"

#include <chrono>
#include <cmath>
#include <thread>

#include "services/common/common_service.h"

namespace navd::localization {

namespace {
void FillPose(const Localizer& localizer, v1::GetPoseResponse* response) {
  const PoseEstimate e = localizer.Estimate();
  if (!e.valid) throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: navd has not received odometry");
  ToProto(e.pose, response->mutable_pose());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) response->add_covariance(e.covariance(r, c));
  ToProto(e.stamp, response->mutable_stamp());
  response->set_localizer(localizer.name());
  response->set_quality(e.quality);
}
}  // namespace

grpc::Status LocalizationService::GetPose(grpc::ServerContext*, const v1::GetPoseRequest*,
                                          v1::GetPoseResponse* response) {
  return GuardedCall([&] { FillPose(localizer_, response); });
}

grpc::Status LocalizationService::GlobalRelocalize(grpc::ServerContext*, const v1::GlobalRelocalizeRequest*,
                                                   v1::GlobalRelocalizeResponse*) {
  return GuardedCall([&] {
    if (!localizer_.GlobalRelocalize()) {
      throw Error(ErrorCode::kFailedPrecondition, "no localisation method here can relocalise globally");
    }
  });
}

grpc::Status LocalizationService::ListMethods(grpc::ServerContext*, const v1::ListMethodsRequest*,
                                              v1::ListMethodsResponse* response) {
  return GuardedCall([&] {
    for (const auto& m : localizer_.Methods()) response->add_methods(m);
    response->set_selected(localizer_.name());
  });
}

grpc::Status LocalizationService::SelectMethod(grpc::ServerContext*, const v1::SelectMethodRequest* request,
                                               v1::SelectMethodResponse*) {
  return GuardedCall([&] { localizer_.Select(request->method()); });
}

grpc::Status LocalizationService::StreamPose(grpc::ServerContext* context, const v1::StreamPoseRequest* request,
                                             grpc::ServerWriter<v1::GetPoseResponse>* writer) {
  double rate = request->rate_hz() == 0.0 ? 10.0 : request->rate_hz();
  if (!(rate > 0.0 && rate <= 50.0)) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "rate_hz must be in (0, 50]");
  }
  const auto period = std::chrono::duration<double>(1.0 / rate);
  auto next = std::chrono::steady_clock::now();
  while (!context->IsCancelled()) {
    v1::GetPoseResponse pose;
    grpc::Status s = GuardedCall([&] { FillPose(localizer_, &pose); });
    if (!s.ok()) return s;
    if (!writer->Write(pose)) break;
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    std::this_thread::sleep_until(next);
  }
  return grpc::Status::OK;
}

grpc::Status LocalizationService::SetPose(grpc::ServerContext*, const v1::SetPoseRequest* request,
                                          v1::SetPoseResponse*) {
  return GuardedCall([&] {
    if (!request->has_pose()) throw Error(ErrorCode::kInvalidArgument, "pose is missing");
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    if (request->covariance_size() != 0) {
      if (request->covariance_size() != 9) {
        throw Error(ErrorCode::kInvalidArgument, "covariance must have 9 entries (row-major 3x3), got " +
                                                     std::to_string(request->covariance_size()));
      }
      for (int i = 0; i < 9; ++i) cov(i / 3, i % 3) = request->covariance(i);
    }
    const Pose2 pose = FromProto(request->pose());
    if (const auto map = maps_.Get(); map && pose.finite()) {
      if (!map->grid.ContainsPoint(pose.translation())) {
        throw Error(ErrorCode::kInvalidArgument, "pose " + FormatPoint(pose.translation()) + " lies outside the map");
      }
      if (map->grid.IsOccupied(map->grid.CellOf(pose.translation()))) {
        throw Error(ErrorCode::kInvalidArgument, "pose " + FormatPoint(pose.translation()) + " is inside an obstacle");
      }
    }
    localizer_.SetPose(pose, cov);
  });
}

}  // namespace navd::localization
