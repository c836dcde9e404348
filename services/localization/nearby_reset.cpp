#include "services/localization/nearby_reset.h"

#include <algorithm>

namespace navd::localization {

std::optional<NearbyReset::Found> NearbyReset::Check(const GlobalScanSearch& search, const Pose2& estimate,
                                                     double quality, const std::vector<Point2>& points,
                                                     const Expected* expected) const {
  if (!o_.enabled || !(quality < o_.below_quality)) return std::nullopt;
  const double contradicted = search.SeeThrough(estimate, points, o_.see_through_margin);
  // A pose awaiting confirmation was found by a scan that contradicted the estimate; along a
  // corridor the next may not, and the pose is looked for all the same.
  if (contradicted <= 0.0 && !expected) return std::nullopt;
  // Around the estimate, unless the pose expected has left its reach.
  const bool follow =
      expected && Distance(expected->pose.translation(), estimate.translation()) + expected->tolerance_xy > o_.radius;
  const SearchWindow window{follow ? expected->pose : estimate, o_.radius, o_.max_turn, o_.blocks_refined};
  const std::vector<PoseCandidate> candidates = search.Search(points, &window);
  if (candidates.empty() || candidates.front().score < o_.min_score) return std::nullopt;
  const double misfit_there = 1.0 - search.Score(estimate, points);
  if (1.0 - candidates.front().score > o_.misfit_ratio * misfit_there) return std::nullopt;
  // Fewer beams through walls than from the estimate; as few will do only for the pose expected.
  const double its = search.SeeThrough(candidates.front().pose, points, o_.see_through_margin);
  if (its > contradicted || (its == contradicted && !(expected && Confirms(*expected, candidates.front().pose))))
    return std::nullopt;
  Found found{candidates.front(), {}};
  for (size_t i = 1; i < candidates.size() && static_cast<int>(found.rivals.size()) < o_.max_rivals; ++i) {
    const PoseCandidate& c = candidates[i];
    if (c.score >= o_.min_score && !PosesWithin(c.pose, found.best.pose, o_.rival_distance, o_.rival_turn))
      found.rivals.push_back(c);
  }
  return found;
}

NearbyReset::Expected NearbyReset::Expect(const Pose2& found, const Pose2& found_at, const Pose2& now) const {
  const double travel = Distance(found_at.translation(), now.translation());
  return {found * (found_at.inverse() * now), o_.confirm_xy + o_.confirm_xy_per_metre * travel,
          o_.confirm_theta + o_.confirm_theta_per_metre * travel};
}

bool NearbyReset::Confirms(const Expected& expected, const Pose2& found) const {
  return PosesWithin(expected.pose, found, expected.tolerance_xy, expected.tolerance_theta);
}

std::vector<Pose2> NearbyReset::ConfirmWhereCarried(const GlobalScanSearch& search, const Found& found,
                                                    const Pose2& found_at, const Pose2& now, const Pose2& estimate,
                                                    const std::vector<Point2>& points) const {
  const double misfit_there = 1.0 - search.Score(estimate, points);
  const double contradicted = search.SeeThrough(estimate, points, o_.see_through_margin);
  // Where the scan fits each pose carried on, best first; a hypothesis that fits as a find must
  // counts, whether or not it is the one confirmed.
  std::vector<PoseCandidate> fits;
  auto try_pose = [&](const Pose2& pose) {
    const Expected expected = Expect(pose, found_at, now);
    const SearchWindow window{expected.pose, expected.tolerance_xy, expected.tolerance_theta, o_.blocks_refined};
    const std::vector<PoseCandidate> candidates = search.Search(points, &window);
    if (candidates.empty() || candidates.front().score < o_.min_score ||
        1.0 - candidates.front().score > o_.misfit_ratio * misfit_there ||
        search.SeeThrough(candidates.front().pose, points, o_.see_through_margin) > contradicted)
      return;
    fits.push_back(candidates.front());
  };
  try_pose(found.best.pose);
  for (const PoseCandidate& rival : found.rivals) try_pose(rival.pose);
  std::sort(fits.begin(), fits.end(), [](const PoseCandidate& a, const PoseCandidate& b) { return a.score > b.score; });
  // Two hypotheses carried onto one place are one; another that the best fits no more than
  // decisively better is confirmed beside it, and the next scans choose.
  std::vector<Pose2> confirmed;
  for (const PoseCandidate& fit : fits) {
    const bool again = std::any_of(confirmed.begin(), confirmed.end(), [&](const Pose2& pose) {
      return PosesWithin(fit.pose, pose, o_.rival_distance, o_.rival_turn);
    });
    if (!again && (confirmed.empty() || 1.0 - fits.front().score >= o_.misfit_ratio * (1.0 - fit.score)))
      confirmed.push_back(fit.pose);
  }
  return confirmed;
}

Pose2 NearbyReset::Settle(const GlobalScanSearch& search, const Pose2& carried,
                          const std::vector<Point2>& points) const {
  const SearchWindow window{carried, o_.carried_xy, o_.carried_theta, o_.blocks_refined};
  const std::vector<PoseCandidate> candidates = search.Search(points, &window);
  return candidates.empty() ? carried : candidates.front().pose;
}

}  // namespace navd::localization
