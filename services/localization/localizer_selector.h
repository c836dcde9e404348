#pragma once
// Several localisers run side by side on the same odometry and scans; one of them, selected by
// name at run time, answers for the robot's pose. The foundation for the chapter-10 arbiter,
// which will choose by context instead of by request.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "services/localization/localizer.h"

namespace navd::localization {

class LocalizerSelector : public Localizer {
 public:
  // The first localiser added is selected until Select says otherwise.
  void Add(std::unique_ptr<Localizer> localizer);
  std::vector<std::string> Methods() const;
  // Throws navd::Error(kInvalidArgument) listing the known methods for an unknown name.
  void Select(const std::string& name);

  std::string name() const override;  // the selected method's
  void AddOdometry(const OdometryReading& reading) override;
  bool AddScan(const ScanReading& scan) override;
  PoseEstimate Estimate() const override;
  bool GlobalRelocalize() override;   // on every localiser that can; true if any did

 private:
  void ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) override;

  std::vector<std::unique_ptr<Localizer>> localizers_;  // fixed after start-up
  mutable std::mutex mutex_;
  size_t selected_ = 0;
  Localizer& Selected() const;
};

}  // namespace navd::localization
