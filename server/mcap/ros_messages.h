// The ROS 2 messages of an MCAP export: their definitions (schema data with encoding
// "ros2msg", each followed by the definitions it uses, as rosbag2 writes them) and their
// CDR encodings (cdr_writer.h).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mbstream::mcap {

// builtin_interfaces/msg/Time from ns since the epoch.
struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  static RosTime FromNanoseconds(std::uint64_t ns);
};

inline constexpr char kJointStateName[] = "sensor_msgs/msg/JointState";
inline constexpr char kTfMessageName[] = "tf2_msgs/msg/TFMessage";
inline constexpr char kStringName[] = "std_msgs/msg/String";
extern const char kJointStateDefinition[];
extern const char kTfMessageDefinition[];
extern const char kStringDefinition[];

// sensor_msgs/msg/JointState with header.frame_id "". `effort` may be null (count 0).
void EncodeJointState(std::string& out, RosTime stamp, const std::vector<std::string>& names,
                      const double* position, const double* velocity, std::size_t count,
                      const double* effort, std::size_t effort_count);

// One geometry_msgs/msg/TransformStamped: child_frame_id's pose in frame_id.
struct Transform {
  std::string_view frame_id;
  std::string_view child_frame_id;
  double translation[3] = {0, 0, 0};  // m
  double rotation[4] = {0, 0, 0, 1};  // quaternion x, y, z, w
};

// tf2_msgs/msg/TFMessage, every transform stamped `stamp`.
void EncodeTfMessage(std::string& out, RosTime stamp, const std::vector<Transform>& transforms);

// std_msgs/msg/String.
void EncodeString(std::string& out, std::string_view text);

}  // namespace mbstream::mcap
