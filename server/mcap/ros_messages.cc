#include "server/mcap/ros_messages.h"

#include "server/mcap/cdr_writer.h"

namespace mbstream::mcap {

namespace {

#define MBSTREAM_ROS_HEADER_DEFINITIONS                                                \
  "================================================================================\n" \
  "MSG: std_msgs/Header\n"                                                             \
  "builtin_interfaces/Time stamp\n"                                                    \
  "string frame_id\n"                                                                  \
  "================================================================================\n" \
  "MSG: builtin_interfaces/Time\n"                                                     \
  "int32 sec\n"                                                                        \
  "uint32 nanosec\n"

void PutHeader(CdrWriter& cdr, RosTime stamp, std::string_view frame_id) {
  cdr.Int32(stamp.sec);
  cdr.UInt32(stamp.nanosec);
  cdr.String(frame_id);
}

}  // namespace

RosTime RosTime::FromNanoseconds(std::uint64_t ns) {
  return RosTime{static_cast<std::int32_t>(ns / 1000000000u),
                 static_cast<std::uint32_t>(ns % 1000000000u)};
}

const char kJointStateDefinition[] =
    "std_msgs/Header header\n"
    "\n"
    "string[] name\n"
    "float64[] position\n"
    "float64[] velocity\n"
    "float64[] effort\n" MBSTREAM_ROS_HEADER_DEFINITIONS;

const char kTfMessageDefinition[] =
    "geometry_msgs/TransformStamped[] transforms\n"
    "================================================================================\n"
    "MSG: geometry_msgs/TransformStamped\n"
    "std_msgs/Header header\n"
    "string child_frame_id\n"
    "Transform transform\n" MBSTREAM_ROS_HEADER_DEFINITIONS
    "================================================================================\n"
    "MSG: geometry_msgs/Transform\n"
    "Vector3 translation\n"
    "Quaternion rotation\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Vector3\n"
    "float64 x\n"
    "float64 y\n"
    "float64 z\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Quaternion\n"
    "float64 x 0\n"
    "float64 y 0\n"
    "float64 z 0\n"
    "float64 w 1\n";

const char kStringDefinition[] = "string data\n";

void EncodeJointState(std::string& out, RosTime stamp, const std::vector<std::string>& names,
                      const double* position, const double* velocity, std::size_t count,
                      const double* effort, std::size_t effort_count) {
  CdrWriter cdr(out);
  PutHeader(cdr, stamp, "");
  cdr.UInt32(static_cast<std::uint32_t>(names.size()));
  for (const std::string& name : names) cdr.String(name);
  cdr.Float64Sequence(position, count);
  cdr.Float64Sequence(velocity, count);
  cdr.Float64Sequence(effort, effort == nullptr ? 0 : effort_count);
}

void EncodeTfMessage(std::string& out, RosTime stamp, const std::vector<Transform>& transforms) {
  CdrWriter cdr(out);
  cdr.UInt32(static_cast<std::uint32_t>(transforms.size()));
  for (const Transform& transform : transforms) {
    PutHeader(cdr, stamp, transform.frame_id);
    cdr.String(transform.child_frame_id);
    for (double v : transform.translation) cdr.Float64(v);
    for (double v : transform.rotation) cdr.Float64(v);
  }
}

void EncodeString(std::string& out, std::string_view text) {
  CdrWriter cdr(out);
  cdr.String(text);
}

}  // namespace mbstream::mcap
