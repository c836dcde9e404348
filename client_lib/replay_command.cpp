#include "client_lib/replay_command.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "client_lib/navd_client.h"
#include "client_lib/replay_link.h"
#include "services/common/carmen_log.h"
#include "services/common/carmen_odometry.h"
#include "services/common/odometry_noise.h"
#include "services/common/quantile.h"
#include "services/common/scan_reach.h"
#include "services/common/text_file.h"
#include "services/common/tum_trajectory.h"
#include "services/mapping/odometry_pairing.h"

namespace navd::navctl {
namespace {

using Clock = std::chrono::steady_clock;
// Clock and odometry between scans, per log second: enough for navd's control loop (20 Hz of its
// clock) to see fresh odometry, capped in wall terms so fast replays do not flood DDS.
constexpr double kTicksPerLogSecond = 20.0;
constexpr double kMaxTicksPerWallSecond = 400.0;

std::string Format(const char* format, double value) {
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string Seconds(double s) { return Format("%.1f", s); }

// The odometry slip at log time t (s since the first scan): a translation in the odom frame
// growing linearly to (dx, dy) over the ramp.
Pose2 SlipAt(const ReplayOptions& o, double since_start) {
  if (o.disturbance != Disturbance::kSlip || since_start <= o.disturb_at) return Pose2{};
  const double f = o.slip_ramp > 0.0 ? std::min(1.0, (since_start - o.disturb_at) / o.slip_ramp) : 1.0;
  return {f * o.disturb_dx, f * o.disturb_dy, 0.0};
}

// When a disturbance happens, in log time: `shown` is when the scans first show it (the drop-off
// of a kidnap, the start of a slip), `over` when it is complete. A kidnap skips the scans after
// `pick` up to `drop`.
struct DisturbancePlan {
  size_t pick = 0, drop = 0;
  double shown = 0.0, over = 0.0;
  double moved = 0.0;  // m the robot or its odometry was moved
};

DisturbancePlan PlanDisturbance(const CarmenLog& log, const ReplayOptions& o) {
  const double t0 = log.scans.front().timestamp;
  DisturbancePlan plan;
  plan.shown = plan.over = t0 + o.disturb_at;
  plan.moved = std::hypot(o.disturb_dx, o.disturb_dy);
  if (o.disturbance == Disturbance::kSlip) plan.over += o.slip_ramp;
  if (o.disturbance != Disturbance::kKidnap) return plan;
  while (plan.pick + 1 < log.scans.size() && log.scans[plan.pick].timestamp < t0 + o.disturb_at) ++plan.pick;
  // The first pick-up at or after T whose drop-off point the robot passes later in the log.
  for (; plan.pick + 1 < log.scans.size(); ++plan.pick) {
    const Point2 target = log.scans[plan.pick].pose * Point2(o.disturb_dx, o.disturb_dy);
    double nearest = std::numeric_limits<double>::infinity();
    for (size_t j = plan.pick + 1; j < log.scans.size(); ++j) {
      const double d = Distance(log.scans[j].pose.translation(), target);
      if (d < nearest) nearest = d, plan.drop = j;
    }
    if (nearest <= o.carry_tolerance) break;
  }
  if (plan.pick + 1 >= log.scans.size())
    throw std::runtime_error("--kidnap " + Seconds(o.disturb_at) +
                             ",...: from no scan after it does the log have the robot within " +
                             Seconds(o.carry_tolerance) + " m of the drop-off point later on; pick another T or DX,DY");
  const Pose2& picked = log.scans[plan.pick].pose;
  plan.shown = plan.over = log.scans[plan.drop].timestamp;
  plan.moved = Distance(log.scans[plan.drop].pose.translation(), picked.translation());
  return plan;
}

// The odometry of a kidnap: standing still from the pick-up to the drop-off, then going on from
// there as the robot moves.
void HoldOdometryWhileCarried(const DisturbancePlan& plan, std::vector<Pose2>* odometry) {
  const Pose2 held = (*odometry)[plan.pick];
  const Pose2 from_drop = (*odometry)[plan.drop].inverse();
  for (size_t j = plan.pick + 1; j < odometry->size(); ++j)
    (*odometry)[j] = j < plan.drop ? held : held * (from_drop * (*odometry)[j]);
}

// Log seconds between the odometry messages the replay sends between scans.
double ReplayTick(const ReplayOptions& o) {
  return std::max(1.0 / kTicksPerLogSecond, o.rate / kMaxTicksPerWallSecond);
}

// The corrected pose at `stamp` on the straight line from scan a to scan b (the log has no truth
// between its scans).
Pose2 CorrectedBetween(const CarmenScan& a, const CarmenScan& b, double stamp) {
  const double span = b.timestamp - a.timestamp;
  return Interpolate(a.pose, b.pose, span > 0 ? std::clamp((stamp - a.timestamp) / span, 0.0, 1.0) : 1.0);
}

// Scan `k` is one the kidnapped robot's laser never showed navd (it was being carried).
bool Carried(const ReplayOptions& o, const DisturbancePlan& plan, size_t k) {
  return o.disturbance == Disturbance::kKidnap && k > plan.pick && k < plan.drop;
}

struct AtScans {
  int judged = 0;
  double sq_pos = 0.0, worst = 0.0;
};
// The pose navd holds right after each scan, where offline localisation is judged: the last it
// published stamped no later than one replay tick after the scan (navd stamps a pose with the
// newest odometry; the scan comes right after the odometry of its instant, and navd has taken it
// in by the next tick), against the corrected pose at its stamp. Later poses are carried on by the
// noisy odometry, where only the corrected poses' straight-line interpolation tells the truth:
// the "every pose" figure judges those.
AtScans JudgeAtScans(const CarmenLog& log, const std::vector<StampedPose>& sorted, const ReplayOptions& o,
                     const DisturbancePlan& plan) {
  const double within = ReplayTick(o) * (1.0 + 1e-9);  // s of log
  AtScans a;
  size_t p = 0;
  for (size_t k = 0; k < log.scans.size(); ++k) {
    if (Carried(o, plan, k)) continue;  // navd never saw it
    const double from = log.scans[k].timestamp;
    const double until = k + 1 < log.scans.size() ? std::min(from + within, log.scans[k + 1].timestamp) : from + within;
    while (p < sorted.size() && sorted[p].stamp < from) ++p;
    const StampedPose* last = nullptr;
    for (size_t q = p; q < sorted.size() && sorted[q].stamp < until; ++q) last = &sorted[q];
    if (!last) continue;
    const Pose2 truth = CorrectedBetween(log.scans[k], log.scans[std::min(k + 1, log.scans.size() - 1)], last->stamp);
    const double e = std::hypot(last->pose.x - truth.x, last->pose.y - truth.y);
    a.sq_pos += e * e;
    a.worst = std::max(a.worst, e);
    ++a.judged;
  }
  return a;
}

// The first log time at or after `from` when navd's error is back within `within` m to stay: the
// median error of the next `hold` s of poses within it. -1 if never.
double BackWithin(const std::vector<std::pair<double, double>>& errors, double from, double within, double hold) {
  for (size_t i = 0; i < errors.size(); ++i) {
    if (errors[i].first < from || errors[i].second > within) continue;
    std::vector<double> next;
    for (size_t j = i; j < errors.size() && errors[j].first <= errors[i].first + hold; ++j)
      next.push_back(errors[j].second);
    if (Quantile(std::move(next), 0.5) <= within) return errors[i].first;
  }
  return -1.0;
}

// Polls navd's GetStatus while the log plays and keeps the first log time at or after `from` at
// which navd said its pose was lost: lost now, or lost (and found) since the last poll.
class LostWatch {
 public:
  LostWatch(const std::string& server, double from, const std::atomic<double>& log_time)
      : from_(from), log_time_(log_time) {
    ClientOptions copts;
    copts.server = server;
    client_ = std::make_unique<Client>(copts);
    thread_ = std::thread([this] { Run(); });
  }
  ~LostWatch() {
    stop_ = true;
    thread_.join();
  }
  double first_lost() const { return first_lost_; }  // log time, or -1

 private:
  void Run() {
    while (!stop_) {
      // The log plays on while navd answers: a reply counts as before `from` only if the log had not
      // reached it when the reply came, and a loss is dated no later than when it was asked for.
      const double asked = log_time_.load();
      try {
        const auto status = client_->GetStatus();
        if (log_time_.load() < from_) {
          losses_before_ = status.localization_losses();
        } else if (first_lost_ < 0.0 && (status.localization_lost() || status.localization_losses() > losses_before_)) {
          first_lost_ = std::max(asked, from_);
        }
      } catch (const std::exception&) {
        // navd busy or gone for a moment: the next poll tells.
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  double from_;
  const std::atomic<double>& log_time_;
  std::unique_ptr<Client> client_;
  std::atomic<bool> stop_{false};
  std::atomic<double> first_lost_{-1.0};
  uint64_t losses_before_ = 0;  // navd's count of losses before `from`
  std::thread thread_;
};

// The log as the replay plays it: its scans (paced or re-timed when their stamps cannot time a
// replay), the odometry at each and the disturbance planned on it.
struct PreparedLog {
  CarmenLog log;
  std::vector<Pose2> odometry;  // one per scan, odom frame
  DisturbancePlan plan;
};

PreparedLog PrepareLog(const ReplayOptions& o) {
  const OdometryNoise noise = ParseOdometryNoise(o.odom_noise);
  const std::optional<OdometryPairing> given_pairing = ParseOdometryPairing(o.pairing, "--pairing");
  PreparedLog p;
  CarmenLog& log = p.log;
  log = ReadCarmenLog(o.log, o.strict);
  if (log.skipped_lines > 0) std::fprintf(stderr, "navctl replay: skipped %d malformed lines\n", log.skipped_lines);
  if (o.max_scans > 0 && log.scans.size() > static_cast<size_t>(o.max_scans)) log.scans.resize(o.max_scans);
  if (log.scans.size() < 2) throw std::runtime_error(o.log + ": fewer than two laser scans to replay");
  if (o.odometry != "noisy" && o.odometry != "log")
    throw std::runtime_error("--odometry must be noisy or log, not '" + o.odometry + "'");
  // Taken at the log's own stamps, before the scans are re-timed below.
  std::string how;
  p.odometry = mapping::ReplayOdometryAtScans(
      log, o.odometry == "log" ? mapping::OdometrySource::kLog : mapping::OdometrySource::kNoisy, given_pairing, noise,
      o.seed, &how);
  if (!how.empty()) std::printf("replay: odometry: %s\n", how.c_str());
  if (PaceScansWhenStampsAreCoarse(log)) {
    std::printf(
        "replay: the log's scan stamps are too coarse to time by; scans paced from its odometry (0.5 m/s, 0.5 "
        "rad/s)\n");
  } else if (const int moved = TimeScansInFileOrder(log)) {
    std::printf(
        "replay: %d scans stamped before the scan ahead of them in the file, or sooner after it than a robot moves "
        "(3 m/s, 4 rad/s), follow it that late\n",
        moved);
  }
  const bool disturbed = o.disturbance != Disturbance::kNone;
  if (disturbed && o.disturb_at >= log.scans.back().timestamp - log.scans.front().timestamp)
    throw std::runtime_error("--kidnap/--slip at " + Seconds(o.disturb_at) + " s is past the log's end (" +
                             Seconds(log.scans.back().timestamp - log.scans.front().timestamp) + " s)");
  if (disturbed && o.server.empty())
    throw std::runtime_error("--kidnap/--slip needs --server to ask navd whether it knows it is lost");
  if (disturbed) p.plan = PlanDisturbance(log, o);
  if (o.disturbance == Disturbance::kKidnap) HoldOdometryWhileCarried(p.plan, &p.odometry);
  return p;
}

// The odometry at log time `t` as the robot sends it (slipped while a slip is under way).
void SendOdometry(const ReplayOptions& o, const PreparedLog& p, double t, const Pose2& odometry, ReplayLink& link) {
  const Pose2 slip = SlipAt(o, t - p.log.scans.front().timestamp);
  link.PublishOdometry(t, {odometry.x + slip.x, odometry.y + slip.y, odometry.theta});
}

// navd first hears the robot standing at the first scan, then is told where that is (gRPC SetPose,
// tried until navd answers or o.wait runs out); what it published before is dropped.
void TellFirstPose(const ReplayOptions& o, const PreparedLog& p, ReplayLink& link) {
  const double t0 = p.log.scans.front().timestamp;
  const Pose2& first = p.log.scans.front().pose;
  SendOdometry(o, p, t0, p.odometry.front(), link);
  ClientOptions copts;
  copts.server = o.server;
  Client client(copts);
  const auto until = Clock::now() + std::chrono::duration<double>(o.wait);
  while (true) {
    SendOdometry(o, p, t0, p.odometry.front(), link);
    try {
      client.SetPose(first.x, first.y, first.theta);
      link.TakePoses();
      return;
    } catch (const std::exception& e) {
      if (Clock::now() > until) throw std::runtime_error(std::string("navd refused the first pose: ") + e.what());
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
}

// Plays the log at o.rate log seconds per wall second: each scan at its stamp with the odometry
// of that instant just before it, and odometry and clock every replay tick between scans,
// interpolated. `log_time` follows the clock sent. Returns the wall seconds it took, including
// half a second for navd's last estimates.
double PlayLog(const ReplayOptions& o, const PreparedLog& p, ReplayLink& link, std::atomic<double>& log_time) {
  const std::vector<CarmenScan>& scans = p.log.scans;
  const double t0 = scans.front().timestamp, tick = ReplayTick(o);
  auto send_odometry = [&](double t, const Pose2& odometry) {
    SendOdometry(o, p, t, odometry, link);
    log_time = t;
  };
  auto send_scan = [&](const CarmenScan& s) {
    link.PublishScan(
        s, std::min(s.no_return_range(), ScanReach(s.ranges, s.no_return_range(), {o.range_max, o.far_range_max})));
  };
  if (o.server.empty()) send_odometry(t0, p.odometry.front());
  const auto wall0 = Clock::now();
  auto pace = [&](double t) {
    std::this_thread::sleep_until(wall0 + std::chrono::duration<double>((t - t0) / o.rate));
  };
  size_t next = 1;  // scan 0 is where the robot stands (navd was told so, with --server); sent here at t0
  send_scan(scans.front());
  for (double t = t0 + tick; next < scans.size();) {
    const CarmenScan& s = scans[next];
    if (s.timestamp <= t) {
      pace(s.timestamp);
      send_odometry(s.timestamp, p.odometry[next]);
      if (!Carried(o, p.plan, next)) send_scan(s);
      ++next;
      if (next % 100 == 0 || next == scans.size())
        std::fprintf(stderr, "\r  replayed %zu/%zu scans", next, scans.size());
      continue;
    }
    pace(t);
    const double span = s.timestamp - scans[next - 1].timestamp;
    const double f = span > 0 ? (t - scans[next - 1].timestamp) / span : 1.0;
    send_odometry(t, Interpolate(p.odometry[next - 1], p.odometry[next], std::clamp(f, 0.0, 1.0)));
    t += tick;
  }
  std::fprintf(stderr, "\n");
  // The last estimates come after the last scan.
  send_odometry(scans.back().timestamp + tick, p.odometry.back());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  return std::chrono::duration<double>(Clock::now() - wall0).count();
}

// When navd declared the pose lost (`lost`, log time, -1: never) after the disturbance and when its
// error (stamp, m) was back within 0.1 m to stay, in one line.
void ReportDisturbance(const ReplayOptions& o, const PreparedLog& p,
                       const std::vector<std::pair<double, double>>& errors, double lost) {
  const CarmenLog& log = p.log;
  const DisturbancePlan& plan = p.plan;
  const double t0 = log.scans.front().timestamp;
  double peak = 0.0;
  for (const auto& [stamp, error] : errors)
    if (stamp >= plan.shown && stamp <= plan.shown + 60.0) peak = std::max(peak, error);
  const double back = BackWithin(errors, plan.over, 0.1, 2.0);
  const std::string what =
      o.disturbance == Disturbance::kKidnap
          ? "carried " + Format("%.2f", plan.moved) + " m at " + Seconds(log.scans[plan.pick].timestamp - t0) + " s (" +
                std::to_string(plan.drop - plan.pick - 1) + " scans over " +
                Seconds(log.scans[plan.drop].timestamp - log.scans[plan.pick].timestamp) + " s unseen, odometry still)"
          : "odometry slipped " + Format("%.2f", plan.moved) + " m at " + Seconds(o.disturb_at) + " s";
  std::printf("%s: %s; navd %s; worst error after %.2f m; %s\n",
              o.disturbance == Disturbance::kKidnap ? "kidnap" : "slip", what.c_str(),
              lost >= 0.0 ? ("declared the pose lost " + Seconds(lost - plan.shown) + " s later").c_str()
                          : "never declared the pose lost",
              peak,
              back >= 0.0 ? ("back within 0.1 m " + Seconds(back - plan.shown) + " s after it").c_str()
                          : "never back within 0.1 m");
}

// navd's poses judged against the corrected poses (each at its stamp, and at the scans), written
// to o.out as TUM, and with a disturbance when navd declared itself lost and was back. Returns the
// exit code: 1 when navd published no pose.
int Report(const ReplayOptions& o, const PreparedLog& p, std::vector<StampedPose> got, const LostWatch* lost_watch,
           double wall, const std::string& pose_topic) {
  const CarmenLog& log = p.log;
  const DisturbancePlan& plan = p.plan;
  const double t0 = log.scans.front().timestamp, t_end = log.scans.back().timestamp;
  // Each pose against the corrected trajectory at its stamp.
  double sq_pos = 0, sq_head = 0, worst = 0;
  int judged = 0;
  std::vector<std::pair<double, double>> errors;  // (stamp, position error)
  std::string tum;
  size_t k = 1;
  // Stable: of poses with one stamp, the last received is navd's latest word on that instant.
  std::stable_sort(got.begin(), got.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.stamp < b.stamp; });
  for (const StampedPose& got_pose : got) {
    if (got_pose.stamp < t0 || got_pose.stamp > t_end) continue;
    while (k + 1 < log.scans.size() && log.scans[k].timestamp < got_pose.stamp) ++k;
    const Pose2 truth = CorrectedBetween(log.scans[k - 1], log.scans[k], got_pose.stamp);
    const double ep = std::hypot(got_pose.pose.x - truth.x, got_pose.pose.y - truth.y);
    const double eh = std::abs(NormalizeAngle(got_pose.pose.theta - truth.theta));
    sq_pos += ep * ep;
    sq_head += eh * eh;
    worst = std::max(worst, ep);
    errors.emplace_back(got_pose.stamp, ep);
    ++judged;
    tum += FormatTumLine(got_pose.stamp, got_pose.pose);
  }
  if (!o.out.empty()) WriteFileAtomically(o.out, tum);
  const AtScans at_scans = JudgeAtScans(log, got, o, plan);
  std::printf("replay: %zu scans, %.0f s of log in %.1f s (%.0fx real time)\n", log.scans.size(), t_end - t0, wall,
              wall > 0 ? (t_end - t0) / wall : 0.0);
  if (judged == 0) {
    std::printf("navd published no poses on %s\n", pose_topic.c_str());
    return 1;
  }
  std::printf("navd: %d poses, position RMSE %.4f m, heading RMSE %.4f rad, worst %.3f m%s\n", judged,
              std::sqrt(sq_pos / judged), std::sqrt(sq_head / judged), worst,
              worst > 0.5 ? " (lost at times)" : ", never lost");
  if (at_scans.judged > 0) {
    std::printf("navd at scans: %d scans, position RMSE %.4f m, worst %.3f m\n", at_scans.judged,
                std::sqrt(at_scans.sq_pos / at_scans.judged), at_scans.worst);
  }
  if (lost_watch) ReportDisturbance(o, p, errors, lost_watch->first_lost());
  return 0;
}

}  // namespace

void ParseDisturbance(const std::string& flag, const std::string& text, Disturbance kind, ReplayOptions* options) {
  double t = 0, dx = 0, dy = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &t, &dx, &dy, &tail) != 3 || !std::isfinite(t) || !std::isfinite(dx) ||
      !std::isfinite(dy) || t < 0.0)
    throw std::runtime_error(
        flag + " must be T,DX,DY: seconds of log time (>= 0) and metres in the robot's frame, got '" + text + "'");
  if (options->disturbance != Disturbance::kNone)
    throw std::runtime_error(flag + ": one of --kidnap and --slip at a time");
  options->disturbance = kind;
  options->disturb_at = t;
  options->disturb_dx = dx;
  options->disturb_dy = dy;
}

int RunReplay(const ReplayOptions& o) {
  if (!(o.rate > 0.0) || !std::isfinite(o.rate)) throw std::runtime_error("--rate must be a positive number");
  const PreparedLog prepared = PrepareLog(o);
  ReplayLink link({o.domain, o.dds_security, o.robot_namespace});
  link.WaitForNavd(o.wait);
  const double t0 = prepared.log.scans.front().timestamp;
  std::atomic<double> log_time{t0};
  if (!o.server.empty()) TellFirstPose(o, prepared, link);
  std::unique_ptr<LostWatch> lost_watch;
  if (o.disturbance != Disturbance::kNone)
    lost_watch = std::make_unique<LostWatch>(o.server, t0 + o.disturb_at, log_time);
  const double wall = PlayLog(o, prepared, link, log_time);
  return Report(o, prepared, link.TakePoses(), lost_watch.get(), wall, link.pose_topic());
}

}  // namespace navd::navctl
