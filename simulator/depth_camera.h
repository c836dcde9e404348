#pragma once
// A depth camera (default: an Intel RealSense D435 at 212 x 120) ray-cast against the world in
// 3-D: walls and the hidden boxes stand floor to ceiling, solids fill their height band, bodies
// (robots, people, moving obstacles) are upright cylinders, and the floor is the plane z = 0.
// Depth noise grows with the square of the depth, and some pixels read nothing (holes), as a
// stereo camera's do. Points are in the camera's optical frame (x right, y down, z ahead; metres).
// Walls are cast once per sliver of bearing as wide as a pixel, not per pixel: every pixel whose
// ray heads that way shares the 2-D cast, and a sliver between two casts that meet one surface
// takes their mean; the floor's depth follows from each pixel's ray; a solid or body is tested only
// on the pixels its bounding box's image covers; the noise and the holes come from a table drawn
// once, read from a random place each frame; and the per-pixel pass is written for the
// vectorizer. A 25,000-pixel image costs under a tenth of a millisecond, so navsim with the camera
// stays about 500 times faster than real time.
#include <Eigen/Core>
#include <random>
#include <vector>

#include "services/common/camera_frame.h"
#include "services/common/ray_caster.h"
#include "services/common/world.h"
#include "services/common/disc.h"
#include "simulator/scenario.h"

namespace navd::sim {

class DepthCamera {
 public:
  // m: how tall bodies are to the camera (people, and robots carrying nothing taller).
  static constexpr double kBodyHeight = 1.8;

  explicit DepthCamera(const DepthCameraDescription& description);
  // The points seen from a robot at `pose` (map frame), row by row, pixels without a reading left
  // out. `walls`: the truth without the solids' cells; discs with id `self` are not seen.
  std::vector<Eigen::Vector3f> Capture(const Pose2& pose, const RayCaster& walls, const std::vector<Solid>& solids,
                                       const std::vector<Disc>& discs, int self, std::mt19937_64& rng) const;
  const DepthCameraDescription& description() const { return d_; }

 private:
  // The pixels [u0, u1] x [v0, v1] a box's image can cover (empty when u0 > u1).
  struct PixelRect {
    int u0, u1, v0, v1;
  };
  // A box (corners relative to the camera, map axes) to the pixels it can cover: the bounding
  // rectangle of the image of what of it lies in front of the camera.
  PixelRect CoverOf(const Eigen::Matrix3f& to_optical, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) const;

  // A wall cast: which sliver, its bearing's unit vector in the robot frame, and how far across
  // the floor (m) any pixel on it can see.
  struct Cast {
    uint16_t sliver;
    Point2 dir;
    float reach;
  };
  DepthCameraDescription d_;
  PinholeIntrinsics intrinsics_;
  Eigen::Matrix3f to_robot_;        // optical frame directions to the robot frame (x ahead, y left, z up)
  std::vector<float> column_x_;     // optical x per metre of depth, by column
  std::vector<float> row_y_;        // optical y per metre of depth, by row
  std::vector<uint16_t> sliver_;    // per pixel, row by row: the bearing sliver its walls come from
  std::vector<float> per_across_;   // per pixel: m of depth per m across the floor
  std::vector<float> floor_depth_;  // per pixel: m of depth to the floor (huge when it looks up)
  double sliver_width_ = 0.0;       // rad of bearing per wall cast
  int slivers_ = 0;                 // slivers round the full circle
  std::vector<Cast> casts_;         // the slivers some pixel heads into
  std::vector<float> noise_;        // depth noise per square metre of depth; NaN marks a hole
  double max_reach_ = 0.0;          // m across the floor, the farthest any pixel looks
};

}  // namespace navd::sim
