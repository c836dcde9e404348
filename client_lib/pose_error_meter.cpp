#include "client_lib/pose_error_meter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dds/conversions.h"

namespace navd {

namespace {
constexpr double kTruthKept = 5.0;  // s of truth history
}  // namespace

void PoseErrorMeter::AddTruth(double stamp, const Pose2& truth) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!truth_.empty() && stamp <= truth_.back().first) {
    if (stamp < truth_.back().first - 1.0)
      truth_.clear();  // the simulator restarted
    else
      return;
  }
  const double travelled =
      odometer_.empty() || truth_.empty()
          ? 0.0
          : odometer_.back().second + Distance(truth.translation(), truth_.back().second.translation());
  odometer_.emplace_back(stamp, travelled);
  truth_.emplace_back(stamp, truth);
  while (truth_.front().first < stamp - kTruthKept) truth_.pop_front();
  MatchLocked();
}

void PoseErrorMeter::AddEstimate(double stamp, const Pose2& estimate) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.emplace_back(stamp, estimate);
  MatchLocked();
}

void PoseErrorMeter::SetWindow(double from, double to) {
  std::lock_guard<std::mutex> lock(mutex_);
  from_ = from;
  to_ = to;
}

void PoseErrorMeter::MatchLocked() {
  while (!pending_.empty() && !truth_.empty()) {
    const auto [stamp, est] = pending_.front();
    if (stamp > truth_.back().first) return;  // its truth has not arrived yet
    pending_.pop_front();
    if (stamp < truth_.front().first) continue;  // too old to match
    size_t i = 1;
    while (i < truth_.size() && truth_[i].first < stamp) ++i;
    Pose2 truth = truth_.front().second;
    if (i < truth_.size()) {
      const auto& [ta, a] = truth_[i - 1];
      const auto& [tb, b] = truth_[i];
      const double s = tb > ta ? (stamp - ta) / (tb - ta) : 1.0;
      truth = Interpolate(a, b, s);
    }
    errors_.push_back(
        {stamp, Distance(est.translation(), truth.translation()), std::abs(NormalizeAngle(est.theta - truth.theta))});
  }
}

double PoseErrorMeter::TimeToTravel(double distance, double from) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto first = std::lower_bound(odometer_.begin(), odometer_.end(), std::make_pair(from, -1e300));
  if (first == odometer_.end()) return -1.0;
  for (auto it = first; it != odometer_.end(); ++it) {
    if (it->second - first->second >= distance) return it->first - first->first;
  }
  return -1.0;
}

PoseErrorFigures PoseErrorMeter::Figures() const {
  std::lock_guard<std::mutex> lock(mutex_);
  PoseErrorFigures f;
  double sum = 0, sum_sq = 0, heading = 0;
  for (const Sample& err : errors_) {
    if (err.stamp < from_ || err.stamp > to_) continue;
    const double e = err.position;
    ++f.samples;
    sum += e;
    sum_sq += e * e;
    heading += err.heading;
    f.max_position = std::max(f.max_position, e);
  }
  if (f.samples > 0) {
    f.mean_position = sum / f.samples;
    f.rms_position = std::sqrt(sum_sq / f.samples);
    f.mean_heading = heading / f.samples;
  }
  return f;
}

MeasuredRun StartMeasuring(PoseErrorMeter& meter, const dds::ParticipantOptions& dds,
                           const std::string& robot_namespace, PeopleProximityMeter* proximity) {
  TelemetryOptions topts;
  topts.dds = dds;
  topts.robot_namespace = robot_namespace;
  MeasuredRun run;
  run.telemetry = std::make_unique<Telemetry>(
      topts, nullptr,
      [&meter](const nav_msgs::msg::dds_::Odometry_& m) {
        meter.AddTruth(dds::FromTime(m.header().stamp()), dds::FromPose(m.pose().pose()));
      },
      [&meter](const geometry_msgs::msg::dds_::PoseWithCovarianceStamped_& m) {
        meter.AddEstimate(dds::FromTime(m.header().stamp()), dds::FromPose(m.pose().pose()));
      },
      proximity ? Telemetry::WorldCallback(
                      [proximity](const navsim_msgs::msg::dds_::WorldState_& w) { proximity->AddWorld(w); })
                : Telemetry::WorldCallback{});
  const auto before = run.telemetry->WaitForSimStatus(10.0);
  if (!before) {
    throw std::runtime_error("--measure: no simulator status on DDS domain " + std::to_string(dds.domain) +
                             " within 10 s (is navsim running there?)");
  }
  run.before = *before;
  return run;
}

}  // namespace navd
