#include "services/localization/localizer_selector.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"

namespace navd::localization {

void LocalizerSelector::Add(std::unique_ptr<Localizer> localizer) { localizers_.push_back(std::move(localizer)); }

std::vector<std::string> LocalizerSelector::Methods() const {
  std::vector<std::string> names;
  for (const auto& l : localizers_) names.push_back(l->name());
  names.emplace_back("auto");
  return names;
}

void LocalizerSelector::Select(const std::string& name) {
  if (name == "auto") {
    std::lock_guard<std::mutex> lock(mutex_);
    arbiter_ = std::make_unique<MethodArbiter>();
    last_evaluation_ = -1e18;
    return;
  }
  std::string known;
  for (size_t i = 0; i < localizers_.size(); ++i) {
    if (localizers_[i]->name() == name) {
      std::lock_guard<std::mutex> lock(mutex_);
      selected_ = i;
      arbiter_.reset();
      return;
    }
    known += localizers_[i]->name() + ", ";
  }
  throw Error(ErrorCode::kInvalidArgument,
              "method: unknown localisation method '" + name + "' (known: " + known + "auto)");
}

bool LocalizerSelector::automatic() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return arbiter_ != nullptr;
}

void LocalizerSelector::Arbitrate(double stamp) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!arbiter_ || !std::isfinite(stamp) || stamp < last_evaluation_ + kEvaluationPeriod) return;
  last_evaluation_ = stamp;
  const bool laser_fresh = stamp - last_scan_stamp_ <= kLaserTimeout;
  std::vector<MethodContext> methods;
  for (const auto& l : localizers_) methods.push_back(l->Suitability(laser_fresh));
  selected_ = arbiter_->Update(methods, {std::begin(kWeights), std::end(kWeights)});
}

Localizer& LocalizerSelector::Selected() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return *localizers_.at(selected_);
}

std::string LocalizerSelector::name() const { return Selected().name(); }

void LocalizerSelector::AddOdometry(const OdometryReading& raw) {
  OdometryReading reading;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    reading = jump_filter_.Filter(raw);
    last_odometry_ = reading;
  }
  for (auto& l : localizers_) l->AddOdometry(reading);
  if (const std::shared_ptr<BesideSearch> search = RunningSearch()) search->AddOdometry(reading);
  Arbitrate(reading.stamp);
}

bool LocalizerSelector::AddScan(const ScanReading& scan) {
  bool used = false;
  for (auto& l : localizers_) used |= l->AddScan(scan);
  // The search is fed outside the lock (100 000 particles at first).
  if (const std::shared_ptr<BesideSearch> search = RunningSearch()) search->AddScan(scan);
  // The laser is there when scans arrive, used or not: a filter skips scans while the robot
  // stands still.
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (std::isfinite(scan.stamp)) last_scan_stamp_ = std::max(last_scan_stamp_, scan.stamp);
  }
  Arbitrate(scan.stamp);
  return used;
}

PoseEstimate LocalizerSelector::Estimate() const { return Selected().Estimate(); }

int LocalizerSelector::odometry_jumps() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return jump_filter_.jumps();
}

bool LocalizerSelector::GlobalRelocalize() {
  EndSearch(false);
  bool any = false;
  for (auto& l : localizers_) any |= l->GlobalRelocalize();
  return any;
}

bool LocalizerSelector::SearchAround(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  bool any = false;
  for (auto& l : localizers_) any |= l->SearchAround(pose, covariance);
  return any;
}

bool LocalizerSelector::SetMap(const OccupancyGrid& map) {
  bool any = false;
  for (auto& l : localizers_) any |= l->SetMap(map);
  {
    std::lock_guard<std::mutex> lock(search_mutex_);
    map_version_++;
  }
  if (const std::shared_ptr<BesideSearch> search = RunningSearch()) search->SetMap(map);
  return any;
}

std::shared_ptr<BesideSearch> LocalizerSelector::RunningSearch() const {
  std::lock_guard<std::mutex> lock(search_mutex_);
  return search_;
}

bool LocalizerSelector::StartSearch() {
  uint64_t version = 0;
  {
    std::lock_guard<std::mutex> lock(search_mutex_);
    version = map_version_;
  }
  // The selected method's kind, or the first that can search (under "auto" odometry may answer
  // while the scans fit poorly).
  std::unique_ptr<Localizer> fresh = Selected().Fresh();
  for (size_t i = 0; !fresh && i < localizers_.size(); ++i) fresh = localizers_[i]->Fresh();
  if (!fresh) return false;
  std::optional<OdometryReading> odometry;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    odometry = last_odometry_;
  }
  if (odometry) fresh->AddOdometry(*odometry);  // where the robot is in the odometry frame now
  if (!fresh->GlobalRelocalize()) return false;
  auto search = std::make_shared<BesideSearch>(std::move(fresh), search_on_its_own_thread_);
  std::lock_guard<std::mutex> lock(search_mutex_);
  if (map_version_ != version) return false;  // a new map came meanwhile: the caller searches again
  search_ = std::move(search);
  return true;
}

PoseEstimate LocalizerSelector::SearchEstimate() const {
  const std::shared_ptr<BesideSearch> search = RunningSearch();
  return search ? search->Estimate() : PoseEstimate{};
}

void LocalizerSelector::EndSearch(bool adopt) {
  std::lock_guard<std::mutex> reset(reset_mutex_);
  PoseEstimate found;
  {
    std::lock_guard<std::mutex> lock(search_mutex_);
    if (!search_) return;
    found = search_->Estimate();
    search_.reset();
  }
  if (adopt && found.valid) ResetAll(found.pose, 0.5 * (found.covariance + found.covariance.transpose()));
}

void LocalizerSelector::ResetPose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  std::lock_guard<std::mutex> reset(reset_mutex_);
  {
    std::lock_guard<std::mutex> lock(search_mutex_);
    search_.reset();
  }
  ResetAll(pose, covariance);
}

void LocalizerSelector::ResetAll(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  for (auto& l : localizers_) l->SetPose(pose, covariance);
}

}  // namespace navd::localization
