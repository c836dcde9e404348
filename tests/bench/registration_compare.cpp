// PCL's registration beside navd's own scan matching, on real scans. Pairs of
// consecutive scans of a real log (the corrected poses give the true relative pose) are matched
// from a starting guess off by the log's own odometry error (the documented noise model, seeded),
// by navd's point-to-line ICP (services/mapping/point_to_line_matcher, a hash grid for its
// nearest neighbours), PCL's point-to-point ICP (a FLANN kd-tree for its correspondences) in 3-D
// and with its 2-D transformation estimate, and PCL's 2-D NDT. Prints, per method: the median and 95th percentile
// translation and heading errors, the share of pairs off by more than 0.1 m or 0.05 rad, and the median time per match.
//   registration_compare --log ../shared/data/carmen/intel-corrected.log.gz [--pairs 300] [--seed 1] [--row NAME]
// --row NAME: one row of docs/results.md's table (scripts/registration-table prints the whole table).
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt_2d.h>
#include <pcl/registration/transformation_estimation_2D.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <map>

#include "services/common/carmen_log.h"
#include "services/common/odometry_noise.h"
#include "services/localization/scan_points.h"
#include "services/mapping/point_to_line_matcher.h"

namespace navd {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

std::vector<Point2> EndPoints(const CarmenScan& s) {
  localization::ScanReading r;
  r.ranges = s.ranges;
  r.angle_min = static_cast<float>(s.angle_min);
  r.angle_increment = static_cast<float>(s.angle_increment);
  r.range_max = static_cast<float>(std::min(s.no_return_range(), 40.0));
  r.range_min = 0.05f;
  return localization::ScanEndPoints(r, 0);
}

Cloud::Ptr ToCloud(const std::vector<Point2>& points) {
  auto c = std::make_shared<Cloud>();
  for (const Point2& p : points)
    c->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f));
  return c;
}

Eigen::Matrix4f Matrix(const Pose2& p) {
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m(0, 0) = m(1, 1) = static_cast<float>(std::cos(p.theta));
  m(0, 1) = static_cast<float>(-std::sin(p.theta));
  m(1, 0) = static_cast<float>(std::sin(p.theta));
  m(0, 3) = static_cast<float>(p.x);
  m(1, 3) = static_cast<float>(p.y);
  return m;
}

Pose2 PoseOf(const Eigen::Matrix4f& m) { return {m(0, 3), m(1, 3), std::atan2(m(1, 0), m(0, 0))}; }

struct Pair {
  std::vector<Point2> reference, query;
  Pose2 truth, guess;  // the query's pose in the reference's frame
};

using Method = std::function<Pose2(const Pair&)>;

}  // namespace
}  // namespace navd

int main(int argc, char** argv) {
  using namespace navd;
  CLI::App app{"PCL's registration beside navd's point-to-line ICP on real scan pairs"};
  std::string log_path;
  int pairs_wanted = 300;
  uint64_t seed = 1;
  app.add_option("--log", log_path, "CARMEN log with corrected poses")->required();
  app.add_option("--pairs", pairs_wanted, "Scan pairs to match")->check(CLI::Range(1, 100000));
  app.add_option("--seed", seed, "Seed of the odometry noise of the starting guesses");
  std::string row;
  app.add_option("--row", row,
                 "Print one table row named ROW instead (median mm / mrad, pairs off, ms per method), under a header");
  CLI11_PARSE(app, argc, argv);

  const CarmenLog log = ReadCarmenLog(log_path);
  // Pairs a robot moved between (at least 0.1 m or 0.05 rad), spread over the whole log.
  std::vector<size_t> moved;
  for (size_t i = 0; i + 1 < log.scans.size(); ++i) {
    const Pose2 d = log.scans[i].pose.inverse() * log.scans[i + 1].pose;
    if (d.translation().norm() > 0.1 || std::abs(d.theta) > 0.05) moved.push_back(i);
  }
  const size_t step = std::max<size_t>(1, moved.size() / static_cast<size_t>(pairs_wanted));
  std::vector<Pair> pairs;
  for (size_t k = 0; k < moved.size() && static_cast<int>(pairs.size()) < pairs_wanted; k += step) {
    const size_t i = moved[k];
    Pair p;
    p.reference = EndPoints(log.scans[i]);
    p.query = EndPoints(log.scans[i + 1]);
    p.truth = log.scans[i].pose.inverse() * log.scans[i + 1].pose;
    OdometryCorruptor corruptor(OdometryNoise{}, seed * 1'000'003 + k);
    corruptor.Next(Pose2{});
    p.guess = corruptor.Next(p.truth);  // the noise model's error over this one step
    pairs.push_back(std::move(p));
  }

  std::vector<std::pair<std::string, Method>> methods;
  methods.emplace_back("navd point-to-line ICP (hash grid)", [](const Pair& p) {
    const mapping::PointToLineMatcher matcher(p.reference);
    const mapping::PointToLineResult r = matcher.Match(p.query, p.guess);
    return r.ok ? r.pose : p.guess;
  });
  // PCL's ICP, with its 3-D transformation estimate or its 2-D one.
  auto pcl_icp = [](const Pair& p, bool in_the_plane) {
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
    if (in_the_plane)
      icp.setTransformationEstimation(
          std::make_shared<pcl::registration::TransformationEstimation2D<pcl::PointXYZ, pcl::PointXYZ>>());
    icp.setInputSource(ToCloud(p.query));
    icp.setInputTarget(ToCloud(p.reference));
    icp.setMaxCorrespondenceDistance(0.2);
    icp.setMaximumIterations(30);
    icp.setTransformationEpsilon(1e-8);
    Cloud aligned;
    icp.align(aligned, Matrix(p.guess));
    return icp.hasConverged() ? PoseOf(icp.getFinalTransformation()) : p.guess;
  };
  methods.emplace_back("PCL ICP point-to-point (kd-tree)", [&](const Pair& p) { return pcl_icp(p, false); });
  methods.emplace_back("PCL ICP point-to-point in the plane (kd-tree)",
                       [&](const Pair& p) { return pcl_icp(p, true); });
  methods.emplace_back("PCL NDT 2-D", [](const Pair& p) {
    pcl::NormalDistributionsTransform2D<pcl::PointXYZ, pcl::PointXYZ> ndt;
    ndt.setInputSource(ToCloud(p.query));
    ndt.setInputTarget(ToCloud(p.reference));
    ndt.setMaximumIterations(30);
    ndt.setGridCentre(Eigen::Vector2f(0, 0));
    ndt.setGridExtent(Eigen::Vector2f(40, 40));
    ndt.setGridStep(Eigen::Vector2f(0.5, 0.5));
    ndt.setOptimizationStepSize(Eigen::Vector3d(0.05, 0.05, 0.01));
    ndt.setTransformationEpsilon(1e-6);
    Cloud aligned;
    ndt.align(aligned, Matrix(p.guess));
    return ndt.hasConverged() ? PoseOf(ndt.getFinalTransformation()) : p.guess;
  });

  if (pairs.empty()) {
    std::fprintf(stderr, "registration_compare: %s has no pair of scans the robot moved between\n", log_path.c_str());
    return 1;
  }
  auto quantile = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
  };
  std::vector<double> guess_t, guess_r;
  for (const Pair& p : pairs) {
    const Pose2 e = p.truth.inverse() * p.guess;
    guess_t.push_back(e.translation().norm());
    guess_r.push_back(std::abs(NormalizeAngle(e.theta)));
  }
  std::printf("%zu scan pairs of %s, starting guesses off by median %.1f mm / %.1f mrad (95%%: %.1f mm / %.1f mrad)\n",
              pairs.size(), log_path.c_str(), 1e3 * quantile(guess_t, 0.5), 1e3 * quantile(guess_r, 0.5),
              1e3 * quantile(guess_t, 0.95), 1e3 * quantile(guess_r, 0.95));
  // Per method: median and 95th percentile errors, pairs off, median time.
  struct Figures {
    double t50, t95, r50, r95, ms;
    int off;
  };
  std::vector<Figures> figures;
  for (const auto& [name, match] : methods) {
    std::vector<double> et, er, ms;
    int off = 0;
    for (const Pair& p : pairs) {
      const auto t0 = std::chrono::steady_clock::now();
      const Pose2 found = match(p);
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      const Pose2 e = p.truth.inverse() * found;
      et.push_back(e.translation().norm());
      er.push_back(std::abs(NormalizeAngle(e.theta)));
      off += et.back() > 0.1 || er.back() > 0.05;
    }
    figures.push_back({1e3 * quantile(et, 0.5), 1e3 * quantile(et, 0.95), 1e3 * quantile(er, 0.5),
                       1e3 * quantile(er, 0.95), quantile(ms, 0.5), off});
  }
  if (!row.empty()) {
    std::printf("| log |");
    for (const auto& method : methods) std::printf(" %s: mm / mrad (median), off*, ms |", method.first.c_str());
    std::printf("\n|---|");
    for (size_t m = 0; m < methods.size(); ++m) std::printf("---|");
    std::printf("\n| %s |", row.c_str());
    for (const Figures& f : figures) std::printf(" %.1f / %.1f, %d, %.2f |", f.t50, f.r50, f.off, f.ms);
    std::printf("\n");
    return 0;
  }
  std::printf(
      "| method | translation error mm, median / 95%% | heading error mrad, median / 95%% | off > 0.1 m or 0.05 rad | "
      "ms per match, median |\n|---|---|---|---|---|\n");
  for (size_t m = 0; m < methods.size(); ++m) {
    const Figures& f = figures[m];
    std::printf("| %s | %.1f / %.1f | %.1f / %.1f | %d of %zu | %.2f |\n", methods[m].first.c_str(), f.t50, f.t95,
                f.r50, f.r95, f.off, pairs.size(), f.ms);
  }
  return 0;
}
