#include "services/localization/localization_service.h"

#include <cmath>

#include "services/common/common_service.h"

namespace navd::localization {

grpc::Status LocalizationService::GetPose(grpc::ServerContext*, const v1::GetPoseRequest*,
                                          v1::GetPoseResponse* response) {
  return GuardedCall([&] {
    const PoseEstimate e = localizer_.Estimate();
    if (!e.valid) throw Error(ErrorCode::kFailedPrecondition, "no pose estimate yet: navd has not received odometry");
    ToProto(e.pose, response->mutable_pose());
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) response->add_covariance(e.covariance(r, c));
    ToProto(e.stamp, response->mutable_stamp());
    response->set_localizer(localizer_.name());
    response->set_quality(e.quality);
  });
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
    localizer_.SetPose(FromProto(request->pose()), cov);
  });
}

}  // namespace navd::localization
