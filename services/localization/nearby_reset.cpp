#include "services/localization/nearby_reset.h"

namespace navd::localization {

std::optional<PoseCandidate> NearbyReset::Check(const GlobalScanSearch& search, const Pose2& estimate, double quality,
                                                const std::vector<Point2>& points) const {
  if (!o_.enabled || !(quality < o_.below_quality)) return std::nullopt;
  const double contradicted = search.SeeThrough(estimate, points, o_.see_through_margin);
  if (contradicted <= 0.0) return std::nullopt;
  const SearchWindow window{estimate, o_.radius, o_.max_turn, o_.blocks_refined};
  const std::vector<PoseCandidate> candidates = search.Search(points, &window);
  if (candidates.empty() || candidates.front().score < o_.min_score) return std::nullopt;
  if (1.0 - candidates.front().score > o_.misfit_ratio * (1.0 - search.Score(estimate, points))) return std::nullopt;
  if (search.SeeThrough(candidates.front().pose, points, o_.see_through_margin) >= contradicted) return std::nullopt;
  return candidates.front();
}

}  // namespace navd::localization
