#pragma once
// navd's geometry as JSON messages of Foxglove's well-known schemas (foxglove.Grid,
// foxglove.PoseInFrame, foxglove.PosesInFrame, foxglove.LaserScan, foxglove.FrameTransform), which
// Foxglove Studio's 3-D panel draws, and navd.MovingDiscs (people and moving obstacles with their
// velocity). Each encoder has its schema (JSON Schema text) beside it, for the channel's advert.
// Stamps are seconds of the sender's clock; frames are named by the caller ("map", "base_link").
#include <cstdint>
#include <string>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/pose2.h"

namespace navd::view {

// Seconds -> nanoseconds for FoxgloveServer::Publish (negative stamps as 0).
uint64_t StampNanoseconds(double stamp);
std::string Base64(const uint8_t* data, size_t size);

// foxglove.Grid with one int8 field "occupancy" (-1 unknown, 0 free .. 100 occupied), row 0 at
// the grid's origin (its lower left corner in `frame`), rows going +y: ROS's OccupancyGrid order.
std::string OccupancyGridJson(const OccupancyGrid& grid, double stamp, const std::string& frame);
// foxglove.Grid with one uint8 field "cost" per cell, same layout as the grid it was built on.
std::string CostGridJson(const OccupancyGrid& layout, const std::vector<uint8_t>& cost, double stamp,
                         const std::string& frame);
extern const char* const kGridSchema;

// foxglove.PoseInFrame, plus "covariance": the 3 x 3 covariance of (x, y, yaw), row-major (m², rad²).
std::string PoseJson(const Pose2& pose, const double* covariance3x3, double stamp, const std::string& frame);
extern const char* const kPoseSchema;

// foxglove.PosesInFrame: each point headed towards the next.
std::string PathJson(const std::vector<Point2>& points, double stamp, const std::string& frame);
extern const char* const kPathSchema;

// foxglove.LaserScan in the sensor's frame, beams from start_angle every `increment` (rad).
std::string LaserScanJson(const std::vector<float>& ranges, double start_angle, double increment, double stamp,
                          const std::string& frame);
extern const char* const kLaserScanSchema;

// foxglove.FrameTransform: `child` in `parent`.
std::string FrameTransformJson(const Pose2& child_in_parent, double stamp, const std::string& parent,
                               const std::string& child);
extern const char* const kFrameTransformSchema;

struct MovingDisc {
  std::string id;
  Point2 position = Point2::Zero();  // m, in the message's frame
  Point2 velocity = Point2::Zero();  // m/s
  double radius = 0.25;              // m
  std::string kind;                  // "person", "obstacle", "robot"
};
// navd.MovingDiscs.
std::string MovingDiscsJson(const std::vector<MovingDisc>& discs, double stamp, const std::string& frame);
extern const char* const kMovingDiscsSchema;

}  // namespace navd::view
