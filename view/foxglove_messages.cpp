#include "view/foxglove_messages.h"

#include <cmath>
#include <nlohmann/json.hpp>

namespace navd::view {
namespace {

using Json = nlohmann::json;

// foxglove.NumericType
constexpr int kUint8 = 1;
constexpr int kInt8 = 2;

Json Time(double stamp) {
  const uint64_t ns = StampNanoseconds(stamp);
  return {{"sec", ns / 1000000000ULL}, {"nsec", ns % 1000000000ULL}};
}

Json PoseOf(double x, double y, double yaw) {
  return {{"position", {{"x", x}, {"y", y}, {"z", 0.0}}},
          {"orientation", {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(yaw / 2.0)}, {"w", std::cos(yaw / 2.0)}}}};
}

// A finite number for JSON (which has no NaN or infinity).
double Finite(double v, double otherwise = 0.0) { return std::isfinite(v) ? v : otherwise; }

Json GridOf(const OccupancyGrid& layout, const uint8_t* data, const std::string& field, int type, double stamp,
            const std::string& frame) {
  return {{"timestamp", Time(stamp)},
          {"frame_id", frame},
          {"pose", PoseOf(layout.origin().x(), layout.origin().y(), 0.0)},
          {"column_count", layout.width()},
          {"cell_size", {{"x", layout.resolution()}, {"y", layout.resolution()}}},
          {"row_stride", layout.width()},
          {"cell_stride", 1},
          {"fields", Json::array({{{"name", field}, {"offset", 0}, {"type", type}}})},
          {"data", Base64(data, static_cast<size_t>(layout.width()) * layout.height())}};
}

}  // namespace

uint64_t StampNanoseconds(double stamp) {
  if (!(stamp > 0.0)) return 0;
  return static_cast<uint64_t>(std::llround(stamp * 1e9));
}

std::string Base64(const uint8_t* data, size_t size) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const uint32_t v = (uint32_t{data[i]} << 16) | (uint32_t{data[i + 1]} << 8) | data[i + 2];
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(kAlphabet[(v >> 6) & 63]);
    out.push_back(kAlphabet[v & 63]);
  }
  if (i < size) {
    const uint32_t v = (uint32_t{data[i]} << 16) | (i + 1 < size ? uint32_t{data[i + 1]} << 8 : 0);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(i + 1 < size ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

std::string OccupancyGridJson(const OccupancyGrid& grid, double stamp, const std::string& frame) {
  return GridOf(grid, reinterpret_cast<const uint8_t*>(grid.cells().data()), "occupancy", kInt8, stamp, frame).dump();
}

std::string CostGridJson(const OccupancyGrid& layout, const std::vector<uint8_t>& cost, double stamp,
                         const std::string& frame) {
  return GridOf(layout, cost.data(), "cost", kUint8, stamp, frame).dump();
}

std::string PoseJson(const Pose2& pose, const double* covariance3x3, double stamp, const std::string& frame) {
  Json m = {{"timestamp", Time(stamp)}, {"frame_id", frame}, {"pose", PoseOf(pose.x, pose.y, pose.theta)}};
  Json cov = Json::array();
  for (int i = 0; i < 9; ++i) cov.push_back(covariance3x3 ? Finite(covariance3x3[i]) : 0.0);
  m["covariance"] = cov;
  return m.dump();
}

std::string PathJson(const std::vector<Point2>& points, double stamp, const std::string& frame) {
  Json poses = Json::array();
  for (size_t i = 0; i < points.size(); ++i) {
    const Point2 d = i + 1 < points.size() ? Point2(points[i + 1] - points[i])
                     : i > 0               ? Point2(points[i] - points[i - 1])
                                           : Point2(1.0, 0.0);
    poses.push_back(PoseOf(points[i].x(), points[i].y(), std::atan2(d.y(), d.x())));
  }
  return Json{{"timestamp", Time(stamp)}, {"frame_id", frame}, {"poses", poses}}.dump();
}

std::string LaserScanJson(const std::vector<float>& ranges, double start_angle, double increment, double stamp,
                          const std::string& frame) {
  Json r = Json::array();
  for (float v : ranges) r.push_back(std::isfinite(v) ? static_cast<double>(v) : 0.0);
  const double end = start_angle + increment * (ranges.empty() ? 0.0 : static_cast<double>(ranges.size() - 1));
  return Json{{"timestamp", Time(stamp)},    {"frame_id", frame}, {"pose", PoseOf(0, 0, 0)},
              {"start_angle", start_angle},  {"end_angle", end},  {"ranges", r},
              {"intensities", Json::array()}}
      .dump();
}

std::string FrameTransformJson(const Pose2& child_in_parent, double stamp, const std::string& parent,
                               const std::string& child) {
  const Json p = PoseOf(child_in_parent.x, child_in_parent.y, child_in_parent.theta);
  return Json{{"timestamp", Time(stamp)},
              {"parent_frame_id", parent},
              {"child_frame_id", child},
              {"translation", p["position"]},
              {"rotation", p["orientation"]}}
      .dump();
}

std::string MovingDiscsJson(const std::vector<MovingDisc>& discs, double stamp, const std::string& frame) {
  Json list = Json::array();
  for (const MovingDisc& d : discs) {
    list.push_back({{"id", d.id},
                    {"x", Finite(d.position.x())},
                    {"y", Finite(d.position.y())},
                    {"vx", Finite(d.velocity.x())},
                    {"vy", Finite(d.velocity.y())},
                    {"radius", Finite(d.radius)},
                    {"kind", d.kind}});
  }
  return Json{{"timestamp", Time(stamp)}, {"frame_id", frame}, {"discs", list}}.dump();
}

// --- Schemas (JSON Schema, as Foxglove publishes them for its well-known types) ---------------

#define NAVD_TIME_SCHEMA                                                                                           \
  R"({"type":"object","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0}},)" \
  R"("required":["sec","nsec"]})"
#define NAVD_VECTOR3_SCHEMA \
  R"({"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}}})"
#define NAVD_QUATERNION_SCHEMA                                                                           \
  R"({"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},)" \
  R"("w":{"type":"number"}}})"
#define NAVD_POSE_SCHEMA                                                                                          \
  R"({"type":"object","properties":{"position":)" NAVD_VECTOR3_SCHEMA R"(,"orientation":)" NAVD_QUATERNION_SCHEMA \
  R"(}})"

const char* const kGridSchema =
    R"({"title":"foxglove.Grid","type":"object","properties":{"timestamp":)" NAVD_TIME_SCHEMA
    R"(,"frame_id":{"type":"string"},"pose":)" NAVD_POSE_SCHEMA R"(,"column_count":{"type":"integer","minimum":0},)"
    R"("cell_size":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"}}},)"
    R"("row_stride":{"type":"integer","minimum":0},"cell_stride":{"type":"integer","minimum":0},)"
    R"("fields":{"type":"array","items":{"type":"object","properties":{"name":{"type":"string"},)"
    R"("offset":{"type":"integer","minimum":0},"type":{"type":"integer"}}}},)"
    R"("data":{"type":"string","contentEncoding":"base64"}},)"
    R"("required":["timestamp","frame_id","pose","column_count","cell_size","row_stride","cell_stride","fields","data"]})";

const char* const kPoseSchema =
    R"({"title":"foxglove.PoseInFrame","type":"object","properties":{"timestamp":)" NAVD_TIME_SCHEMA
    R"(,"frame_id":{"type":"string"},"pose":)" NAVD_POSE_SCHEMA
    R"(,"covariance":{"type":"array","items":{"type":"number"},"minItems":9,"maxItems":9,)"
    R"("description":"covariance of (x, y, yaw), row-major"}},"required":["timestamp","frame_id","pose"]})";

const char* const kPathSchema =
    R"({"title":"foxglove.PosesInFrame","type":"object","properties":{"timestamp":)" NAVD_TIME_SCHEMA
    R"(,"frame_id":{"type":"string"},"poses":{"type":"array","items":)" NAVD_POSE_SCHEMA
    R"(}},"required":["timestamp","frame_id","poses"]})";

const char* const kLaserScanSchema =
    R"({"title":"foxglove.LaserScan","type":"object","properties":{"timestamp":)" NAVD_TIME_SCHEMA
    R"(,"frame_id":{"type":"string"},"pose":)" NAVD_POSE_SCHEMA
    R"(,"start_angle":{"type":"number"},"end_angle":{"type":"number"},)"
    R"("ranges":{"type":"array","items":{"type":"number"}},"intensities":{"type":"array","items":{"type":"number"}}},)"
    R"("required":["timestamp","frame_id","pose","start_angle","end_angle","ranges"]})";

const char* const kFrameTransformSchema =
    R"({"title":"foxglove.FrameTransform","type":"object","properties":{"timestamp":)" NAVD_TIME_SCHEMA
    R"(,"parent_frame_id":{"type":"string"},"child_frame_id":{"type":"string"},"translation":)" NAVD_VECTOR3_SCHEMA
    R"(,"rotation":)" NAVD_QUATERNION_SCHEMA
    R"(},"required":["timestamp","parent_frame_id","child_frame_id","translation","rotation"]})";

const char* const kMovingDiscsSchema =
    R"({"title":"navd.MovingDiscs","type":"object","properties":{"timestamp":)" NAVD_TIME_SCHEMA
    R"(,"frame_id":{"type":"string"},"discs":{"type":"array","items":{"type":"object","properties":{)"
    R"("id":{"type":"string"},"x":{"type":"number"},"y":{"type":"number"},"vx":{"type":"number"},)"
    R"("vy":{"type":"number"},"radius":{"type":"number"},"kind":{"type":"string"}}}}},)"
    R"("required":["timestamp","frame_id","discs"]})";

}  // namespace navd::view
