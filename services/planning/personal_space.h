#pragma once
// People's personal space (book chapter 7, Sec. 6): Hall's proxemic zones and the potential field
// of four Gaussians around a person that the chapter's planners minimise (g2 of Eq. 13). Map
// frame, metres, seconds.
#include "services/common/pose2.h"

namespace navd::planning {

// Hall (1963), distance from the person's centre.
inline constexpr double kIntimateZone = 0.45;  // m
inline constexpr double kPersonalZone = 1.2;   // m
inline constexpr double kSocialZone = 3.6;     // m

// The chapter's four Gaussians in the person's frame ("ahead" = the walking direction): Parallel
// (ahead, elongated), Perpendicular (sideways), Rear (behind, round) and the negative Attractor,
// weighted by the person's interest in the robot (0 for passers-by). The chapter gives no
// numbers; sigmas follow Hall's zones (intimate 0.45, personal 1.2 m).
struct PersonCostModel {
  // Weights are cost per second (as a time price of 1): a second at a person's side costs as much
  // as ten seconds of driving.
  double parallel_weight = 20.0, parallel_sigma_ahead = 1.2, parallel_sigma_side = 0.6;
  double perpendicular_weight = 10.0, perpendicular_sigma_ahead = 0.45, perpendicular_sigma_side = 0.9;
  double rear_weight = 15.0, rear_sigma = 0.6;
  double attractor_weight = -5.0, attractor_sigma = 1.8;  // scaled by interest (0..1)
  double interest = 0.0;
  // g2 at `p` for one person at `mu` walking with velocity `v` (m/s).
  double Cost(const Point2& p, const Point2& mu, const Point2& v) const;
};

}  // namespace navd::planning
