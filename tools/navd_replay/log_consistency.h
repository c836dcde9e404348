#pragma once
// navd-replay --mode consistency: how well a log's scans agree with one another at its poses or a
// trajectory's, with no ground truth (services/mapping/scan_consistency.h); --mode slam prints the
// same measure for its estimate and for the log's poses.
#include <string>
#include <vector>

#include "services/common/carmen_log.h"
#include "services/common/pose2.h"

namespace navd::replay {

// The log's laser poses (its corrected ones, in a corrected log), one per scan in file order.
std::vector<Pose2> LogPoses(const CarmenLog& log);

// The log's scans' echoes, one list per scan in file order, robot frame, as the scan consistency
// measures them.
std::vector<std::vector<Point2>> ConsistencyReturns(const CarmenLog& log);

// How well the log's scans agree at a trajectory's poses (`trajectory`, TUM, one line per scan in
// file order) or, without one, at the log's own: the mean, and per scan into `out` (scan, stamp,
// returns scored, mean distance in mm). With `scan` (0 or more) instead: where the other scans
// place that scan, searched every 5 cm up to 0.2 m and every 0.02 rad up to 0.24 rad around its
// pose. Prints one line; returns the exit code; throws std::runtime_error for a trajectory that
// does not fit the log.
int Consistency(const CarmenLog& log, const std::string& trajectory, int scan, const std::string& out);

}  // namespace navd::replay
