#include "services/mapping/log_renderer.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "services/common/disc.h"
#include "services/common/error.h"
#include "services/common/ziggurat_normal.h"

namespace navd::mapping {

CarmenLog RenderLog(const CarmenLog& log, const RayCaster& world, const LogRenderOptions& options) {
  if (log.scans.empty()) throw Error(ErrorCode::kInvalidArgument, "render: the log has no scans");
  if (!(options.step >= 0.0) || !(options.turn > 0.0) || !(options.range_noise >= 0.0) || !(options.no_return > 0.0))
    throw Error(ErrorCode::kInvalidArgument, "render: step and range noise must be >= 0, turn and no-return > 0");
  // The fov as the rendered log's PARAM line is read back.
  const double fov = FovRoundedToHundredthOfDegree(options.fov);
  if (options.beams != 0 && (options.beams < 2 || !(fov > 0.0 && fov <= 2.0 * M_PI + 1e-9)))
    throw Error(ErrorCode::kInvalidArgument,
                "render: a scanner needs at least 2 beams and a fov within (0, 360] degrees, to the hundredth");
  std::mt19937_64 rng(options.seed);
  std::optional<PathWalkers> people;
  if (options.people.count != 0) {  // PathWalkers refuses a negative count
    std::vector<Pose2> path;
    std::vector<double> stamps;
    for (const CarmenScan& s : log.scans) {
      path.push_back(s.pose);
      stamps.push_back(s.timestamp);
    }
    people.emplace(path, stamps, options.people);
  }
  const ZigguratNormal noise(0.0, options.range_noise);
  // The scanner's beams as the log states them: its front laser's PARAM lines place them.
  CarmenLog out;
  out.front_laser_fov = log.front_laser_fov;
  out.front_laser_resolution = log.front_laser_resolution;
  FlaserBeamLayout layout;
  if (options.beams != 0) {
    // Evenly over the fov, as a stated resolution that fits it places them when read back.
    const size_t count = static_cast<size_t>(options.beams);
    layout = FlaserBeams(count, fov, fov / static_cast<double>(FlaserBeamGaps(count, fov)));
    out.front_laser_fov = fov;
    out.front_laser_resolution = layout.angle_increment;
  }
  auto render = [&](const CarmenScan& beams, const Pose2& pose, double stamp) {
    CarmenScan s;
    s.angle_min = options.beams != 0 ? layout.angle_min : beams.angle_min;
    s.angle_increment = options.beams != 0 ? layout.angle_increment : beams.angle_increment;
    s.range_max = beams.range_max > 0.0 ? beams.range_max : options.no_return;
    s.pose = s.odometry = pose;
    s.timestamp = stamp;
    s.ranges.resize(options.beams != 0 ? static_cast<size_t>(options.beams) : beams.ranges.size());
    const std::vector<Disc> bodies = people ? people->At(stamp, pose.translation()) : std::vector<Disc>{};
    const std::vector<const Disc*> nearby = DiscsWithin(bodies, pose.translation(), s.range_max, -1);
    for (size_t i = 0; i < s.ranges.size(); ++i) {
      const double angle = pose.theta + s.angle_min + i * s.angle_increment;
      const double r =
          CastAgainstWorld(world, nearby, pose.translation(), {std::cos(angle), std::sin(angle)}, s.range_max);
      s.ranges[i] = static_cast<float>(
          r >= s.range_max ? s.range_max : std::clamp(r + noise(rng), 0.0, std::nextafter(s.range_max, 0.0)));
    }
    out.scans.push_back(std::move(s));
  };
  for (size_t k = 0; k + 1 < log.scans.size(); ++k) {
    const CarmenScan& a = log.scans[k];
    const CarmenScan& b = log.scans[k + 1];
    const Point2 travel = b.pose.translation() - a.pose.translation();
    const double turn = NormalizeAngle(b.pose.theta - a.pose.theta);
    const int pieces =
        options.step > 0.0
            ? std::max(
                  1, static_cast<int>(std::ceil(std::max(travel.norm() / options.step, std::abs(turn) / options.turn))))
            : 1;
    for (int j = 0; j < pieces; ++j) {
      const double u = static_cast<double>(j) / pieces;
      const Point2 p = a.pose.translation() + u * travel;
      render(a, {p.x(), p.y(), NormalizeAngle(a.pose.theta + u * turn)}, a.timestamp + u * (b.timestamp - a.timestamp));
    }
  }
  render(log.scans.back(), log.scans.back().pose, log.scans.back().timestamp);
  return out;
}

}  // namespace navd::mapping
