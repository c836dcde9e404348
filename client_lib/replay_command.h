#pragma once
// navctl replay: plays a CARMEN log over DDS like a robot (rt/clock in log time, rt/<ns>/odom,
// rt/<ns>/scan) while navd localises with --use-sim-time, and judges navd's published poses
// (rt/<ns>/pose) against the log's corrected poses. The odometry is made from the corrected poses
// with the seeded noise model navd-replay uses (services/common/odometry_noise.h). With a kidnap
// it also reports when navd declared the pose lost (its GetStatus, polled) and when its pose was
// back within 0.1 m.
#include <cstdint>
#include <string>

namespace navd::navctl {

struct ReplayOptions {
  std::string log;                      // CARMEN log, plain or .gz
  double rate = 10.0;                   // log seconds per wall second
  int domain = 0;                       // navd's DDS domain
  std::string robot_namespace;
  std::string server = "127.0.0.1:50051";  // navd's gRPC, to set the first pose ("" to skip)
  std::string odom_noise = "0.05,0.035";
  uint64_t seed = 1;
  int max_scans = 0;                    // 0: the whole log
  double range_max = 15.0;              // m: beams are cut here, as navd-replay's map builder cuts them
  double wait = 10.0;                   // s for navd's DDS readers to appear
  std::string out;                      // TUM file of navd's poses ("" for none)
  bool strict = false;                  // stop at the first malformed log line
  // A kidnap: from `kidnap_at` s of log time after the first scan, the odometry slips by
  // (kidnap_dx, kidnap_dy) m in its own frame over kidnap_ramp s, as if the robot were carried
  // while its wheels turned: the scans disagree with it from then on, and navd must notice and
  // find itself again. The slip is spread over ticks small enough that navd's odometry jump
  // filter does not take it for a glitch. Negative kidnap_at: none.
  double kidnap_at = -1.0;
  double kidnap_dx = 0.0, kidnap_dy = 0.0;
  double kidnap_ramp = 1.0;
};

// "T,DX,DY" into the options' kidnap fields; throws std::runtime_error naming --kidnap.
void ParseKidnap(const std::string& text, ReplayOptions* options);

// Returns the exit code (0 when the log played through). Throws std::runtime_error or
// navd::Error with one readable line for a missing or malformed log, no navd on DDS, or a navd
// that refuses the first pose.
int RunReplay(const ReplayOptions& options);

}  // namespace navd::navctl
