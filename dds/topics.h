#pragma once
// DDS topic names, ROS 2 style ("rt/" prefix). A robot namespace, when given, goes after "rt/".
#include <string>

namespace navd::dds {

inline std::string TopicName(const std::string& robot_namespace, const std::string& name) {
  return robot_namespace.empty() ? "rt/" + name : "rt/" + robot_namespace + "/" + name;
}

inline constexpr const char* kClock = "rt/clock";            // rosgraph_msgs/Clock, global
inline constexpr const char* kScan = "scan";                 // sensor_msgs/LaserScan
inline constexpr const char* kOdom = "odom";                 // nav_msgs/Odometry
inline constexpr const char* kCmdVel = "cmd_vel";            // geometry_msgs/Twist
inline constexpr const char* kGroundTruth = "ground_truth";  // nav_msgs/Odometry, simulator truth
inline constexpr const char* kSimStatus = "sim/status";      // navsim_msgs/SimStatus
inline constexpr const char* kCmdAccel = "cmd_accel";        // geometry_msgs/Accel (unicycle inputs u1, u2)
inline constexpr const char* kSonar = "sonar";               // sensor_msgs/Range, frame_id sonar_<i>
inline constexpr const char* kIr = "ir";                     // sensor_msgs/Range, frame_id ir_<i>
inline constexpr const char* kJointStates = "joint_states";  // sensor_msgs/JointState, wheel encoders
inline constexpr const char* kBumper = "bumper";             // navsim_msgs/BumperState
inline constexpr const char* kPeople = "people";             // people_msgs/People: a people detector's, frame base_link
inline constexpr const char* kWorldState = "rt/sim/world_state";    // navsim_msgs/WorldState, global
inline constexpr const char* kCollisions = "rt/sim/collisions";     // navsim_msgs/CollisionEvent, global
inline constexpr const char* kDoorCommand = "rt/sim/door_command";  // navsim_msgs/DoorCommand, global
inline constexpr const char* kNavStatus = "navd/status";            // navd_msgs/NavStatus
inline constexpr const char* kMap = "map";                          // nav_msgs/OccupancyGrid, map frame
inline constexpr const char* kNextTick = "navd/next_tick";  // rosgraph_msgs/Clock: navd's next control tick (lockstep)
inline constexpr const char* kPose = "pose";                // geometry_msgs/PoseWithCovarianceStamped, map frame
inline constexpr const char* kCameraPoints = "camera/points";  // sensor_msgs/PointCloud2, camera's optical frame
inline constexpr const char* kCostmap = "navd/costmap";        // nav_msgs/OccupancyGrid: the map and what sensors add

}  // namespace navd::dds
