#include "services/common/carmen_log.h"

#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "services/common/error.h"

namespace navd {
namespace {

bool ParseScan(std::istringstream& in, CarmenScan& s) {
  int n = 0;
  if (!(in >> n) || n <= 0 || n > 100000) return false;
  s.ranges.resize(n);
  for (auto& r : s.ranges) {
    double v;
    if (!(in >> v) || !std::isfinite(v)) return false;
    r = static_cast<float>(v);
  }
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

}  // namespace

CarmenLog ReadCarmenLog(const std::string& path, bool strict) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error(ErrorCode::kNotFound, "log file '" + path + "' does not exist");
  gzFile f = gzopen(path.c_str(), "rb");  // reads plain files too
  if (!f) throw Error(ErrorCode::kInvalidArgument, "log file '" + path + "' cannot be read");
  CarmenLog log;
  std::string line;
  std::vector<char> buf(1 << 16);
  int line_no = 0;
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
      ++line_no;
      std::istringstream in(line);
      std::string type;
      if (!(in >> type) || type[0] == '#') continue;
      bool ok = true;
      if (type == "FLASER") {
        CarmenScan s;
        s.line = line_no;
        ok = ParseScan(in, s);
        if (ok) log.scans.push_back(std::move(s));
      } else if (type == "ODOM") {
        CarmenOdometry o;
        o.line = line_no;
        ok = ParseOdometry(in, o);
        if (ok) log.odometry.push_back(o);
      }
      if (!ok) {
        if (strict) throw Error(ErrorCode::kInvalidArgument, path + ":" + std::to_string(line_no) + ": malformed " + type + " line");
        ++log.skipped_lines;
      }
    }
  } catch (...) {
    gzclose(f);
    throw;
  }
  gzclose(f);
  if (log.scans.empty()) throw Error(ErrorCode::kInvalidArgument, path + ": no FLASER scans");
  return log;
}

}  // namespace navd
