#pragma once
// A depth camera (default: an Intel RealSense D435 at 212 x 120) ray-cast against the world in
// 3-D: walls and the hidden boxes stand floor to ceiling, solids fill their height band, bodies
// (robots, people, moving obstacles) are upright cylinders, and the floor is the plane z = 0.
// Depth noise grows with the square of the depth, and some pixels read nothing (holes), as a
// stereo camera's do. Points are in the camera's optical frame (x right, y down, z ahead; metres).
// Walls are cast once per sliver of bearing (a quarter of a degree), not per pixel: every pixel
// whose ray heads that way shares the 2-D cast; the floor's depth is fixed per pixel; solids are
// listed per sliver they span and bodies marked on theirs, so a pixel tests only those; and the noise and the holes
// come from a table drawn once, read from a random place each frame. A 25,000-pixel image costs a fraction of a
// millisecond, so navsim stays hundreds of times faster than real time.
#include <Eigen/Core>
#include <random>
#include <vector>

#include "services/common/ray_caster.h"
#include "services/common/world.h"
#include "simulator/disc.h"
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
  struct Pixel {
    Eigen::Vector3f optical;  // the ray per metre of depth, optical frame (z = 1)
    Eigen::Vector3f robot;    // the same ray in the robot frame (x ahead, y left, z up)
    float horizontal = 0.0f;  // |robot.xy|: metres across the floor per metre of depth
    float per_across = 0.0f;  // 1 / horizontal: metres of depth per metre across the floor
    float floor = 0.0f;       // depth at which the ray meets the floor (infinity: never)
    int bin = 0;              // the bearing sliver its walls come from
  };
  DepthCameraDescription d_;
  std::vector<Pixel> pixels_;
  std::vector<float> noise_;    // standard normal draws; NaN marks a hole
  std::vector<int> bins_used_;  // slivers some pixel heads into
  double max_reach_ = 0.0;      // m across the floor at range_max, the farthest any pixel looks
};

}  // namespace navd::sim
