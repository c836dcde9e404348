#include "services/mapping/odometry_pairing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "services/common/quantile.h"
#include "services/common/scan_reach.h"
#include "services/mapping/correlative_scan_matcher.h"

namespace navd::mapping {

namespace {

// The scan's returns within its reach (ScanReach: near walls, or far ones in an open hall).
std::vector<Point2> Returns(const CarmenScan& scan, const ScanReachOptions& reach) {
  return ScanReturns(scan.ranges, scan.angle_min, scan.angle_increment, scan.no_return_range(),
                     ScanReach(scan.ranges, scan.no_return_range(), reach));
}

}  // namespace

std::vector<OdometryPairing> OdometryPairingCandidates() {
  std::vector<OdometryPairing> out{OdometryPairing{}};
  for (int quarter = 0; quarter <= 4; ++quarter) out.push_back({false, 0.25 * quarter});
  return out;
}

OdometryPairingEstimate EstimateOdometryPairing(const CarmenLog& log, const OdometryPairingOptions& o) {
  OdometryPairingEstimate out;
  if (!HasStampedOdometry(log)) return out;
  out.candidates = OdometryPairingCandidates();
  out.disagreement.assign(out.candidates.size(), 0.0);
  if (log.scans.size() < 2) return out;
  std::vector<std::vector<Pose2>> odometry;
  for (const OdometryPairing& c : out.candidates) odometry.push_back(OdometryAtScans(log, c));
  // Each window is centred halfway by file place (candidate 3: by stamp, then 0, 1/4, 1/2, ...).
  const std::vector<Pose2>& middle = odometry.at(3);

  struct Pair {
    size_t scan;
    Pose2 centre;
    double window_xy, window_theta;
  };
  std::vector<Pair> informative;
  for (size_t k = 1; k < log.scans.size(); ++k) {
    const Pose2 centre = middle[k - 1].inverse() * middle[k];
    double spread_xy = 0.0, spread_theta = 0.0;
    for (const std::vector<Pose2>& c : odometry) {
      const Pose2 d = centre.inverse() * (c[k - 1].inverse() * c[k]);
      spread_xy = std::max(spread_xy, std::hypot(d.x, d.y));
      spread_theta = std::max(spread_theta, std::abs(d.theta));
    }
    if (spread_xy < o.min_spread_xy && spread_theta < o.min_spread_theta) continue;
    const double window_xy = spread_xy + o.margin_xy, window_theta = spread_theta + o.margin_theta;
    if (window_xy > o.max_window_xy || window_theta > o.max_window_theta) continue;
    informative.push_back({k, centre, window_xy, window_theta});
  }
  const size_t take = std::min(informative.size(), static_cast<size_t>(std::max(o.max_pairs, 0)));
  std::vector<std::vector<double>> disagreements(out.candidates.size());
  for (size_t i = 0; i < take; ++i) {
    const Pair& p = informative[i * informative.size() / take];
    std::vector<Point2> reference = Returns(log.scans[p.scan - 1], o.reach);
    const std::vector<Point2> points = ThinPoints(Returns(log.scans[p.scan], o.reach), o.point_spacing);
    if (static_cast<int>(reference.size()) < o.min_points || static_cast<int>(points.size()) < o.min_points) continue;
    ScanMatchOptions window;
    window.window_xy = p.window_xy;
    window.window_theta = p.window_theta;
    const CorrelationGrid grid(reference, window.resolution, window.sigma);
    const ScanMatch match = MatchScan(grid, points, p.centre, window);
    if (match.score < o.min_score) continue;
    Pose2 step = match.pose;
    const PointToLineResult polished = PointToLineMatcher(std::move(reference), o.polish).Match(points, step);
    const Pose2 moved = step.inverse() * polished.pose;
    if (polished.ok && std::hypot(moved.x, moved.y) < o.polish_max_shift_xy &&
        std::abs(moved.theta) < o.polish_max_shift_theta)
      step = polished.pose;
    ++out.pairs;
    for (size_t c = 0; c < out.candidates.size(); ++c) {
      const Pose2 d = step.inverse() * (odometry[c][p.scan - 1].inverse() * odometry[c][p.scan]);
      disagreements[c].push_back(std::hypot(d.x, d.y) + o.metres_per_radian * std::abs(d.theta));
    }
  }
  for (size_t c = 0; c < out.candidates.size(); ++c) out.disagreement[c] = Quantile(std::move(disagreements[c]), 0.5);
  if (out.pairs < o.min_pairs) return out;
  out.decided = true;
  const auto best = std::min_element(out.disagreement.begin(), out.disagreement.end());
  out.pairing = out.candidates[static_cast<size_t>(best - out.disagreement.begin())];
  return out;
}

std::string Summary(const OdometryPairingEstimate& e) {
  if (e.given) return "ODOM lines paired " + Describe(e.pairing) + ", as asked";
  if (e.candidates.empty()) return "the scans' own odometry fields (no stamped ODOM lines)";
  if (!e.decided)
    return "ODOM lines paired " + Describe(e.pairing) + ": too few scan pairs (" + std::to_string(e.pairs) +
           ") to tell otherwise";
  std::string out = "ODOM lines paired " + Describe(e.pairing) + ", as " + std::to_string(e.pairs) +
                    " scan pairs matched agree (median step disagreement, m:";
  char field[64];
  for (size_t i = 0; i < e.candidates.size(); ++i) {
    const OdometryPairing& c = e.candidates[i];
    if (c.by_stamp) {
      std::snprintf(field, sizeof field, " by stamp %.3f;", e.disagreement[i]);
    } else {
      std::snprintf(field, sizeof field, " at %.2f %.3f%s", c.position, e.disagreement[i],
                    i + 1 < e.candidates.size() ? "," : ")");
    }
    out += field;
  }
  return out;
}

std::vector<Pose2> PairedOdometryAtScans(const CarmenLog& log, const std::optional<OdometryPairing>& given,
                                         OdometryPairingEstimate* estimate) {
  OdometryPairingEstimate found;
  if (given && HasStampedOdometry(log)) {
    found.pairing = *given;
    found.given = true;
  } else if (!given) {
    found = EstimateOdometryPairing(log);
  }
  std::vector<Pose2> out = OdometryAtScans(log, found.pairing);
  if (estimate) *estimate = std::move(found);
  return out;
}

std::vector<Pose2> ReplayOdometryAtScans(const CarmenLog& log, OdometrySource source,
                                         const std::optional<OdometryPairing>& given, const OdometryNoise& noise,
                                         uint64_t seed, std::string* how) {
  if (source == OdometrySource::kNoisy) return NoisyOdometryAtScans(log, noise, seed);
  OdometryPairingEstimate estimate;
  std::vector<Pose2> out = PairedOdometryAtScans(log, given, &estimate);
  if (how) *how = Summary(estimate);
  return out;
}

}  // namespace navd::mapping
