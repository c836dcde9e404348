#pragma once
// Measures how far a pose estimate is from the truth of the same instant: estimates (navd's
// rt/<ns>/pose, stamped with the time they describe) are matched with ground truth (navsim's
// rt/<ns>/ground_truth, 50 Hz) interpolated at the estimate's stamp. This is seed 000's figure of
// merit: the time average of the position and heading error (section 6, footnote 8). Samples may
// arrive in any order from two DDS threads; thread-safe. Metres, radians, seconds.
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "client_lib/people_proximity_meter.h"
#include "client_lib/telemetry.h"
#include "services/common/pose2.h"

namespace navd {

struct PoseErrorFigures {
  size_t samples = 0;
  double mean_position = 0.0;  // m
  double max_position = 0.0;   // m
  double rms_position = 0.0;   // m
  double mean_heading = 0.0;   // rad, absolute
};

class PoseErrorMeter {
 public:
  void AddTruth(double stamp, const Pose2& truth);
  void AddEstimate(double stamp, const Pose2& estimate);
  // Only estimates stamped in [from, to] count (e.g. while a mission runs); default: all.
  void SetWindow(double from, double to);
  PoseErrorFigures Figures() const;
  // Simulated seconds from `from` until the true path length since `from` reached `distance`
  // metres; negative when it has not (yet).
  double TimeToTravel(double distance, double from) const;

 private:
  void MatchLocked();

  mutable std::mutex mutex_;
  std::deque<std::pair<double, Pose2>> truth_;    // by stamp, a few seconds
  std::deque<std::pair<double, Pose2>> pending_;  // estimates newer than the newest truth
  struct Sample {
    double stamp, position, heading;
  };
  std::vector<Sample> errors_;                       // per matched estimate
  std::vector<std::pair<double, double>> odometer_;  // (stamp, true path length so far)
  double from_ = -1e300, to_ = 1e300;
};

// A DDS subscriber (`dds`: domain, name, security) feeding `meter` with navsim's truth and navd's
// estimates, and the
// simulator's status when it started: how navctl's --measure judges a run. Throws
// std::runtime_error when navsim does not report within 10 s.
struct MeasuredRun {
  std::unique_ptr<Telemetry> telemetry;
  navsim_msgs::msg::dds_::SimStatus_ before;
};
// With `proximity`, the simulator's bodies feed it too (how near people the robot came).
MeasuredRun StartMeasuring(PoseErrorMeter& meter, const dds::ParticipantOptions& dds,
                           const std::string& robot_namespace, PeopleProximityMeter* proximity = nullptr);

}  // namespace navd
