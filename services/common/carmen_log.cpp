#include "services/common/carmen_log.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "services/common/carmen_odometry.h"
#include "services/common/error.h"

namespace navd {
namespace {

// One reading: a number, or as logs converted from ROS write them, inf (no return within the
// scanner's range) or nan (no reading), which stream extraction refuses. Either is no echo
// downstream; inf also clears as a no-return does.
bool ReadRange(std::istringstream& in, float& r) {
  std::string token;
  if (!(in >> token)) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(token.c_str(), &end);
  // A number beyond a float (1e400 overflows to inf here) is a corrupt line, not a no-return.
  if (end == token.c_str() || *end != '\0' || errno == ERANGE ||
      (std::isfinite(v) && std::abs(v) > std::numeric_limits<float>::max()))
    return false;
  r = static_cast<float>(v);
  return true;
}

bool ParseScan(std::istringstream& in, CarmenScan& s) {
  int n = 0;
  if (!(in >> n) || n <= 0 || n > kMaxScanBeams) return false;
  s.ranges.resize(n);
  for (auto& r : s.ranges)
    if (!ReadRange(in, r)) return false;
  double x, y, t, ox, oy, ot;
  if (!(in >> x >> y >> t >> ox >> oy >> ot >> s.timestamp)) return false;
  s.pose = {x, y, NormalizeAngle(t)};
  s.odometry = {ox, oy, NormalizeAngle(ot)};
  return s.pose.finite() && s.odometry.finite() && std::isfinite(s.timestamp);
}

bool ParseOdometry(std::istringstream& in, CarmenOdometry& o) {
  double x, y, t, tv, rv, acc;
  if (!(in >> x >> y >> t >> tv >> rv >> acc >> o.timestamp)) return false;
  o.pose = {x, y, NormalizeAngle(t)};
  return o.pose.finite() && std::isfinite(o.timestamp);
}

// The part ROBOTLASER1 and RAWLASER1 lines share, after the message type:
//   laser_type start_angle fov resolution max_range accuracy remission_mode n r1..rn n_remissions rem1..
bool ParseLaserReadings(std::istringstream& in, CarmenScan& s) {
  int type = 0, remission_mode = 0, n = 0;
  double start, fov, res, max_range, accuracy;
  if (!(in >> type >> start >> fov >> res >> max_range >> accuracy >> remission_mode >> n)) return false;
  if (n <= 0 || n > kMaxScanBeams || !std::isfinite(start) || !std::isfinite(res) || !std::isfinite(max_range))
    return false;
  s.ranges.resize(n);
  for (auto& r : s.ranges)
    if (!ReadRange(in, r)) return false;
  int remissions = 0;
  if (!(in >> remissions) || remissions < 0 || remissions > kMaxScanBeams) return false;
  for (int i = 0; i < remissions; ++i) {
    double v;
    if (!(in >> v)) return false;
  }
  s.angle_min = start;
  s.angle_increment = res;
  s.range_max = max_range;
  return true;
}

// ROBOTLASER1 <readings> laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv
//   forward_safety side_safety turn_axis timestamp host logger_timestamp
bool ParseRobotLaser(std::istringstream& in, CarmenScan& s) {
  if (!ParseLaserReadings(in, s)) return false;
  double x, y, t, ox, oy, ot, tv, rv, fs, ss, ta;
  if (!(in >> x >> y >> t >> ox >> oy >> ot >> tv >> rv >> fs >> ss >> ta >> s.timestamp)) return false;
  s.pose = {x, y, NormalizeAngle(t)};
  s.odometry = {ox, oy, NormalizeAngle(ot)};
  return s.pose.finite() && s.odometry.finite() && std::isfinite(s.timestamp);
}

// RAWLASER1 <readings> timestamp host logger_timestamp: the laser's own message, without a pose
// (PoseRawScans gives it the odometry's).
bool ParseRawLaser(std::istringstream& in, CarmenScan& s) {
  return ParseLaserReadings(in, s) && (in >> s.timestamp) && std::isfinite(s.timestamp);
}

// TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta timestamp host logger_timestamp
bool ParseTruth(std::istringstream& in, CarmenTruth& o) {
  double x, y, t, ox, oy, ot;
  if (!(in >> x >> y >> t >> ox >> oy >> ot >> o.timestamp)) return false;
  o.pose = {x, y, NormalizeAngle(t)};
  o.odometry = {ox, oy, NormalizeAngle(ot)};
  return o.pose.finite() && o.odometry.finite() && std::isfinite(o.timestamp);
}

// Parses one line into `log`; false when a known message type is malformed.
// RAWLASER1 scans go to `raw_scans`: they count only in a log without posed scans.
bool ParseLine(const std::string& line, int line_no, CarmenLog& log, std::vector<CarmenScan>& raw_scans,
               std::string& type) {
  std::istringstream in(line);
  type.clear();
  if (!(in >> type) || type[0] == '#') return true;
  if (type == "FLASER" || type == "ROBOTLASER1") {
    CarmenScan s;
    s.line = line_no;
    if (!(type == "FLASER" ? ParseScan(in, s) : ParseRobotLaser(in, s))) return false;
    log.scans.push_back(std::move(s));
  } else if (type == "RAWLASER1") {
    CarmenScan s;
    s.line = line_no;
    if (!ParseRawLaser(in, s)) return false;
    raw_scans.push_back(std::move(s));
  } else if (type == "ODOM") {
    CarmenOdometry o;
    o.line = line_no;
    if (!ParseOdometry(in, o)) return false;
    log.odometry.push_back(o);
  } else if (type == "PARAM") {
    std::string name;
    double value = 0.0;
    if (!(in >> name)) return true;
    type += " " + name;  // a malformed one is named in the error
    if (name == "robot_frontlaser_offset") {
      if (!(in >> value) || !std::isfinite(value) || std::abs(value) > 10.0) return false;
      log.front_laser_offset = value;
    } else if (name == "laser_front_laser_fov") {
      // Radians in some CARMEN versions (3.14159), degrees in others (180): no scanner's field of
      // view is under 7 degrees, nor any over a whole turn.
      if (!(in >> value) || !std::isfinite(value) || value <= 0.0) return false;
      const double fov = FovRoundedToHundredthOfDegree(value > 7.0 ? value * M_PI / 180.0 : value);
      if (fov <= 0.0 || fov > 2.0 * M_PI + 1e-9) return false;
      log.front_laser_fov = fov;
    } else if (name == "laser_front_laser_resolution") {
      // Degrees between beams, as CARMEN's laser module takes it.
      if (!(in >> value) || !std::isfinite(value) || value <= 0.0 || value > 45.0) return false;
      log.front_laser_resolution = value * M_PI / 180.0;
    }
  } else if (type == "TRUEPOS") {
    CarmenTruth o;
    o.line = line_no;
    if (!ParseTruth(in, o)) return false;
    log.truth.push_back(o);
  }
  return true;
}

// A log logged without the robot's own laser messages holds RAWLASER1 scans and ODOM lines: the
// scans are placed where the odometry was at their stamps, as a raw log's FLASER lines are.
void PoseRawScans(CarmenLog& log, std::vector<CarmenScan> raw_scans, const std::string& source) {
  log.scans = std::move(raw_scans);
  if (!HasStampedOdometry(log))
    throw Error(ErrorCode::kInvalidArgument,
                source + ": its RAWLASER1 scans carry no pose, and it has no stamped ODOM lines to place them by");
  const std::vector<Pose2> at_scanner = OdometryAtScans(log, OdometryPairing{});
  const Pose2 centre_from_scanner = Pose2(log.front_laser_offset, 0.0, 0.0).inverse();
  for (size_t i = 0; i < log.scans.size(); ++i) {
    log.scans[i].pose = at_scanner[i];
    log.scans[i].odometry = at_scanner[i] * centre_from_scanner;
  }
}

// FLASER and ROBOTLASER1 are the front laser's old and new messages: a logger that writes both
// writes each scan twice, with one stamp. The FLASER scan (`flaser` indexes log.scans in file
// order) whose stamp a ROBOTLASER1 scan carries is dropped: the new message states its angles. A
// FLASER scan no ROBOTLASER1 scan shares a stamp with (logs joined from two loggers) stays.
void DropFlaserScansWrittenAgain(CarmenLog& log, std::vector<size_t>& flaser) {
  if (flaser.empty() || flaser.size() == log.scans.size()) return;
  std::vector<double> robot_laser_stamps;
  for (size_t i = 0, next = 0; i < log.scans.size(); ++i) {
    if (next < flaser.size() && flaser[next] == i)
      ++next;
    else
      robot_laser_stamps.push_back(log.scans[i].timestamp);
  }
  std::sort(robot_laser_stamps.begin(), robot_laser_stamps.end());
  std::vector<CarmenScan> kept;
  std::vector<size_t> kept_flaser;
  for (size_t i = 0, next = 0; i < log.scans.size(); ++i) {
    const bool is_flaser = next < flaser.size() && flaser[next] == i;
    if (is_flaser) {
      ++next;
      if (std::binary_search(robot_laser_stamps.begin(), robot_laser_stamps.end(), log.scans[i].timestamp)) continue;
      kept_flaser.push_back(kept.size());
    }
    kept.push_back(std::move(log.scans[i]));
  }
  log.scans = std::move(kept);
  flaser = std::move(kept_flaser);
}

// The lines of one log, added in file order, then finished into the log: what ReadCarmenLog and
// ParseCarmenLog share. `source` names the log in errors.
class LogLines {
 public:
  LogLines(std::string source, bool strict) : source_(std::move(source)), strict_(strict) {}

  void Add(const std::string& line) {
    ++line_no_;
    std::string type;
    if (ParseLine(line, line_no_, log_, raw_scans_, type)) {
      if (type == "FLASER") flaser_scans_.push_back(log_.scans.size() - 1);
      return;
    }
    if (strict_)
      throw Error(ErrorCode::kInvalidArgument,
                  source_ + ":" + std::to_string(line_no_) + ": malformed " + type + " line");
    ++log_.skipped_lines;
  }

  CarmenLog Finish() && {
    DropFlaserScansWrittenAgain(log_, flaser_scans_);
    // PARAM lines may follow the first scans; the beams are placed once the whole log is read.
    for (size_t i : flaser_scans_) {
      CarmenScan& s = log_.scans[i];
      const FlaserBeamLayout beams = FlaserBeams(s.ranges.size(), log_.front_laser_fov, log_.front_laser_resolution);
      s.angle_min = beams.angle_min;
      s.angle_increment = beams.angle_increment;
    }
    if (log_.scans.empty() && !raw_scans_.empty()) PoseRawScans(log_, std::move(raw_scans_), source_);
    if (log_.scans.empty())
      throw Error(ErrorCode::kInvalidArgument, source_ + ": no FLASER, ROBOTLASER1 or RAWLASER1 scans");
    const double no_return = InferNoReturnRange(log_);
    for (CarmenScan& s : log_.scans)
      if (s.range_max <= 0.0) s.range_max = no_return;
    return std::move(log_);
  }

 private:
  std::string source_;
  bool strict_;
  int line_no_ = 0;
  CarmenLog log_;
  std::vector<CarmenScan> raw_scans_;  // RAWLASER1 scans, used only in a log without posed scans
  std::vector<size_t> flaser_scans_;   // indices in log_.scans of the FLASER lines' scans
};

}  // namespace

double InferNoReturnRange(const CarmenLog& log) {
  float longest = 0.0f;
  size_t readings = 0;
  for (const CarmenScan& s : log.scans) {
    if (s.range_max > 0.0) continue;
    for (float r : s.ranges) {
      if (!std::isfinite(r)) continue;
      ++readings;
      longest = std::max(longest, r);
    }
  }
  if (readings == 0 || longest < kNoReturnShortest) return 0.0;
  const double threshold = kNoReturnBand * longest;
  size_t at_the_top = 0;
  for (const CarmenScan& s : log.scans)
    if (s.range_max <= 0.0)
      for (float r : s.ranges) at_the_top += std::isfinite(r) && r >= threshold;
  const size_t needed = std::max<size_t>(kNoReturnMinCount, static_cast<size_t>(kNoReturnMinShare * readings));
  return at_the_top >= needed ? threshold : 0.0;
}

bool PaceScansWhenStampsAreCoarse(CarmenLog& log, double speed, double turn_rate, double min_gap) {
  size_t later = 0;
  for (size_t i = 1; i < log.scans.size(); ++i) later += log.scans[i].timestamp > log.scans[i - 1].timestamp;
  if (log.scans.size() < 2 || 2 * later >= log.scans.size() - 1) return false;
  for (size_t i = 1; i < log.scans.size(); ++i) {
    const Pose2 step = log.scans[i - 1].odometry.inverse() * log.scans[i].odometry;
    const double gap = std::max({min_gap, std::hypot(step.x, step.y) / speed, std::abs(step.theta) / turn_rate});
    log.scans[i].timestamp = log.scans[i - 1].timestamp + gap;
  }
  return true;
}

int TimeScansInFileOrder(CarmenLog& log, double max_speed, double max_turn_rate, double gap) {
  int moved = 0;
  for (size_t i = 1; i < log.scans.size(); ++i) {
    const Pose2 step = log.scans[i - 1].pose.inverse() * log.scans[i].pose;
    const double soonest = log.scans[i - 1].timestamp + std::max({gap, std::hypot(step.x, step.y) / max_speed,
                                                                  std::abs(step.theta) / max_turn_rate});
    if (log.scans[i].timestamp >= soonest) continue;
    log.scans[i].timestamp = soonest;
    ++moved;
  }
  return moved;
}

FlaserBeamLayout FlaserBeams(size_t n, double fov, double resolution) {
  const FlaserBeamLayout by_count{CarmenBeamAngle(0, n), n > 1 ? CarmenBeamAngle(1, n) - CarmenBeamAngle(0, n) : 0.0};
  if (n < 2 || fov <= 0.0) return by_count;
  const double gaps = static_cast<double>(FlaserBeamGaps(n, fov));
  // The resolution holds when n beams that far apart span the fov, or the fov less its last beam
  // (loggers that drop a SICK's 361st).
  const double span = gaps * resolution;
  const bool resolution_fits =
      resolution > 0.0 && span >= fov - resolution * (1.0 + 1e-6) && span <= fov + 0.5 * resolution;
  if (!resolution_fits && std::abs(fov - M_PI) < 1e-9) return by_count;  // a SICK's: its modes by the count
  const FlaserBeamLayout by_params{-0.5 * fov, resolution_fits ? resolution : fov / gaps};
  // Where both say the same, the count's guess, to the last bit, as a log without the lines reads.
  const bool same = std::abs(by_params.angle_min - by_count.angle_min) < 1e-9 &&
                    std::abs(by_params.angle_increment - by_count.angle_increment) < 1e-12;
  return same ? by_count : by_params;
}

std::string FormatFlaserLine(const CarmenScan& scan, const std::string& host, double fov, double resolution) {
  const size_t n = scan.ranges.size();
  const FlaserBeamLayout beams = FlaserBeams(n, fov, resolution);
  const bool flaser_angles = n > 0 && std::abs(scan.angle_min - beams.angle_min) < 1e-6 &&
                             (n < 2 || std::abs(scan.angle_increment - beams.angle_increment) < 1e-9);
  if (!flaser_angles) {
    const double degrees = 180.0 / M_PI;
    char what[200];
    std::snprintf(what, sizeof what,
                  "a FLASER line's %zu beams are read back from %.2f degrees, %.4f apart; these start at %.2f, %.4f "
                  "apart",
                  n, beams.angle_min * degrees, beams.angle_increment * degrees, scan.angle_min * degrees,
                  scan.angle_increment * degrees);
    throw Error(ErrorCode::kInvalidArgument, what);
  }
  std::string line = "FLASER " + std::to_string(n);
  char field[64];
  for (const float r : scan.ranges) {
    std::snprintf(field, sizeof field, " %.3f", r);
    line += field;
  }
  for (const Pose2& p : {scan.pose, scan.odometry}) {
    std::snprintf(field, sizeof field, " %.6f %.6f %.6f", p.x, p.y, p.theta);
    line += field;
  }
  std::snprintf(field, sizeof field, " %.6f ", scan.timestamp);
  line += field + host;
  std::snprintf(field, sizeof field, " %.6f\n", scan.timestamp);
  return line + field;
}

CarmenLog ReadCarmenLog(const std::string& path, bool strict) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error(ErrorCode::kNotFound, "log file '" + path + "' does not exist");
  gzFile f = gzopen(path.c_str(), "rb");  // reads plain files too
  if (!f) throw Error(ErrorCode::kInvalidArgument, "log file '" + path + "' cannot be read");
  LogLines lines(path, strict);
  std::string line;
  std::vector<char> buf(1 << 16);
  try {
    while (true) {
      line.clear();
      bool got = false;
      while (gzgets(f, buf.data(), static_cast<int>(buf.size()))) {
        got = true;
        line += buf.data();
        if (!line.empty() && line.back() == '\n') break;
      }
      if (!got) break;
      lines.Add(line);
    }
  } catch (...) {
    gzclose(f);
    throw;
  }
  gzclose(f);
  return std::move(lines).Finish();
}

CarmenLog ParseCarmenLog(const std::string& text, const std::string& source, bool strict) {
  LogLines lines(source, strict);
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.Add(line);
  return std::move(lines).Finish();
}

std::string FormatFlaserLog(const CarmenLog& log, const std::string& host) {
  std::string text;
  char line[160];
  if (log.front_laser_fov > 0.0) {
    std::snprintf(line, sizeof line, "PARAM laser_front_laser_fov %.9f %s 0\n", log.front_laser_fov, host.c_str());
    text += line;
  }
  if (log.front_laser_resolution > 0.0) {
    // Every digit of a double: the beams of a long scan are read back where they were, to the last bit.
    std::snprintf(line, sizeof line, "PARAM laser_front_laser_resolution %.17g %s 0\n",
                  log.front_laser_resolution * 180.0 / M_PI, host.c_str());
    text += line;
  }
  for (const CarmenScan& s : log.scans)
    text += FormatFlaserLine(s, host, log.front_laser_fov, log.front_laser_resolution);
  return text;
}

}  // namespace navd
