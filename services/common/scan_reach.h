#pragma once
// How far a scan's echoes are used. Near walls are where a laser is precise: far echoes spread
// with every milliradian of heading error and graze walls, so they are cut at `near`. A scan that
// finds too little that near (an open hall, a convention centre, a yard) is used out to `far`
// instead: far walls and pillars are all it has to go by. Metres.
#include <cmath>
#include <cstddef>
#include <vector>

#include "services/common/pose2.h"

namespace navd {

// A reading shorter than this (m) is no echo: the scanner's own housing, or an error code that a
// scanner reports as a range (a Hokuyo's 0-19 mm). It says nothing: the mapper neither marks nor
// clears along it, SLAM matches no point and the localisers weigh no beam for it.
constexpr double kMinEchoRange = 0.05;

// Whether reading `r` (m) says anything: an echo or a no-return (+inf, ROS's, included); not NaN,
// -inf or shorter than kMinEchoRange.
inline bool IsReading(double r) { return !std::isnan(r) && r >= kMinEchoRange; }

// Whether reading `r` (m) is an echo: a reading short of `no_return` (and finite).
inline bool IsEcho(double r, double no_return) { return IsReading(r) && r < no_return && std::isfinite(r); }

// A 180-degree SICK's beams at half a degree: the scans whose counts navd's mapping and matching
// options are set for. A scanner with more beams is weighed as that many (ScanReachOptions, the
// SLAM's return budget).
constexpr size_t kSickHalfDegreeBeams = 361;

struct ScanReachOptions {
  double near = 20.0;
  double far = 50.0;
  // Fewer echoes than this within `near` (of 180 to 361 beams: a room's or a corridor's scan has
  // well over a hundred) and the scan reaches `far`. A scan of more than kSickHalfDegreeBeams beams
  // needs as large a share of them as a scan of kSickHalfDegreeBeams does: an open hall seen by a
  // thousand beams is as open as seen by 361.
  int min_near_echoes = 60;
};

// The reach (m) for a scan's `ranges`, readings at or beyond `no_return` being no-returns: near,
// or far for a scan with too few echoes within near.
double ScanReach(const std::vector<float>& ranges, double no_return, const ScanReachOptions& options);

// The echoes of a scan (beam i at angle_min + i x angle_increment, rad) shorter than `reach` and
// than `no_return` (IsEcho), as points in the scanner frame (m), in beam order.
std::vector<Point2> ScanReturns(const std::vector<float>& ranges, double angle_min, double angle_increment,
                                double no_return, double reach);

}  // namespace navd
