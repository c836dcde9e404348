#include "services/localization/localizer_selector.h"

#include "services/common/error.h"

namespace navd::localization {

void LocalizerSelector::Add(std::unique_ptr<Localizer> localizer) { localizers_.push_back(std::move(localizer)); }

std::vector<std::string> LocalizerSelector::Methods() const {
  std::vector<std::string> names;
  for (const auto& l : localizers_) names.push_back(l->name());
  return names;
}

void LocalizerSelector::Select(const std::string& name) {
  std::string known;
  for (size_t i = 0; i < localizers_.size(); ++i) {
    if (localizers_[i]->name() == name) {
      std::lock_guard<std::mutex> lock(mutex_);
      selected_ = i;
      return;
    }
    known += (known.empty() ? "" : ", ") + localizers_[i]->name();
  }
  throw Error(ErrorCode::kInvalidArgument, "method: unknown localisation method '" + name + "' (known: " + known + ")");
}

Localizer& LocalizerSelector::Selected() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return *localizers_.at(selected_);
}

std::string LocalizerSelector::name() const { return Selected().name(); }

void LocalizerSelector::AddOdometry(const OdometryReading& reading) {
  for (auto& l : localizers_) l->AddOdometry(reading);
}

bool LocalizerSelector::AddScan(const ScanReading& scan) {
  bool used = false;
  for (auto& l : localizers_) used |= l->AddScan(scan);
  return used;
}

PoseEstimate LocalizerSelector::Estimate() const { return Selected().Estimate(); }

bool LocalizerSelector::GlobalRelocalize() {
  bool any = false;
  for (auto& l : localizers_) any |= l->GlobalRelocalize();
  return any;
}

void LocalizerSelector::ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  for (auto& l : localizers_) l->SetPose(pose, covariance);
}

}  // namespace navd::localization
