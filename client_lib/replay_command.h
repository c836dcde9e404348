#pragma once
// navctl replay: plays a CARMEN log over DDS like a robot (rt/clock in log time, rt/<ns>/odom,
// rt/<ns>/scan) while navd localises with --use-sim-time, and judges navd's published poses
// (rt/<ns>/pose) against the log's corrected poses. The odometry is made from the corrected poses
// with the seeded noise model navd-replay uses (services/common/odometry_noise.h), or is the log's
// own (ReplayOptions::odometry). With a kidnap
// or a slip it also reports when navd declared the pose lost (its GetStatus, polled) and when its
// pose was back within 0.1 m.
#include <cstdint>
#include <string>

namespace navd::navctl {

// What happens to the robot mid-log, to see whether navd tells a real loss from a disagreement
// it can absorb:
//  - kKidnap: the robot is carried (dx, dy) m, in its own frame, from where it is at that moment.
//    The scans skip to the place later in the log nearest that point, and the
//    odometry stands still meanwhile: navd's estimate is left where the robot was picked up, and
//    only the scans tell it otherwise. navd must declare the pose lost and find itself again.
//  - kSlip: the odometry slips (dx, dy) m in its own frame over slip_ramp s while the scans go on,
//    as wheels spinning on a slippery floor. Each step is small enough that navd's odometry jump
//    filter takes it as motion; the scans say the robot did not move, and navd should follow them.
enum class Disturbance { kNone, kKidnap, kSlip };

struct ReplayOptions {
  std::string log;           // CARMEN log, plain or .gz
  double rate = 10.0;        // log seconds per wall second
  int domain = 0;            // navd's DDS domain
  std::string dds_security;  // DDS Security enclave (navctl --dds-security); empty: none
  std::string robot_namespace;
  std::string server = "127.0.0.1:50051";  // navd's gRPC, to set the first pose ("" to skip)
  // noisy: the log's corrected poses corrupted by odom_noise, seeded (the evaluation protocol);
  // log: the odometry the log holds (ODOM lines, paired with the scans as they agree, or FLASER's
  // odometry fields: mapping::PairedOdometryAtScans), as a robot would send it.
  std::string odometry = "noisy";
  std::string pairing = "auto";  // with odometry "log": ParseOdometryPairing's text
  std::string odom_noise = "0.05,0.035";
  uint64_t seed = 1;
  int max_scans = 0;            // 0: the whole log
  double range_max = 15.0;      // m: beams are cut here, as navd-replay's map builder cuts them,
  double far_range_max = 50.0;  // or here in a scan with too little within range_max (ScanReach)
  double wait = 10.0;           // s for navd's DDS readers to appear
  std::string out;              // TUM file of navd's poses ("" for none)
  bool strict = false;          // stop at the first malformed log line
  // A disturbance `disturb_at` s of log time after the first scan (see Disturbance).
  Disturbance disturbance = Disturbance::kNone;
  double disturb_at = 0.0;                    // s
  double disturb_dx = 0.0, disturb_dy = 0.0;  // m
  double slip_ramp = 1.0;                     // s
  double carry_tolerance = 0.5;               // m: the farthest a drop-off place may be from (dx, dy)
};

// "T,DX,DY" (the value of `flag`) into the options' disturbance fields as `kind`; throws
// std::runtime_error naming the flag.
void ParseDisturbance(const std::string& flag, const std::string& text, Disturbance kind, ReplayOptions* options);

// Returns the exit code (0 when the log played through). Throws std::runtime_error or
// navd::Error with one readable line for a missing or malformed log, no navd on DDS, or a navd
// that refuses the first pose.
int RunReplay(const ReplayOptions& options);

}  // namespace navd::navctl
