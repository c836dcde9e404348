#pragma once
// A log's scans drawn again by ray casting in a map, at the log's own laser poses or at poses
// between them: a log whose poses agree with its scans up to the map's cells and the range noise
// added. On a real corrected log, an estimator's error against the corrected poses mixes its own
// error with the log's: people, glass and the correction's own error make the scans and the poses
// disagree by centimetres. On the log rendered from the map those poses draw, what remains is the
// estimator's. With a step it also turns a log sampled every metre into a dense one, as lidars log
// today, and with people walking its corridors it has passers-by where the map has none.
// Metres, radians, seconds, the log's frame.
#include <cstdint>

#include "services/common/carmen_log.h"
#include "services/common/ray_caster.h"
#include "services/mapping/path_walkers.h"

namespace navd::mapping {

struct LogRenderOptions {
  // Travel (m) and turn (rad) between rendered scans, along the straight line and the even turn
  // from each of the log's poses to the next; step 0: one scan at each of the log's poses.
  double step = 0.0;
  double turn = 0.05;
  double range_noise = 0.01;  // m: standard deviation of the Gaussian noise added to every echo
  // m: the reading of a beam that hits nothing, when the log has no no-return reading of its own
  // (a SICK LMS's 81.91).
  double no_return = 81.91;
  uint64_t seed = 1;
  // The scanner the scans are cast with: `beams` beams over `fov` rad (taken to the hundredth of a
  // degree) centred ahead, evenly apart (a whole turn's beams a turn / beams apart, none twice);
  // 0 beams: each scan the beams of the log's scan it starts from. The rendered log states the
  // fov and spacing as its front laser's (FlaserBeams).
  double fov = 0.0;
  int beams = 0;
  // People walking the log's path (none by default), placed at each rendered scan's stamp: the
  // beams that meet one read their distance to it.
  PathWalkerOptions people;
};

// One scan per pose (see LogRenderOptions) with the beams of the log's scan it starts from, or the
// scanner's the options give; pose, odometry and stamp are the rendered pose's (stamps
// interpolated). Beams that hit nothing within the no-return range read it. Throws navd::Error
// when the log has no scans, a step is negative, or a scanner given has fewer than 2 beams or a
// fov not within (0, 2 pi].
CarmenLog RenderLog(const CarmenLog& log, const RayCaster& world, const LogRenderOptions& options);

}  // namespace navd::mapping
