#include "server/mcap/run_mcap.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "server/kinematics/forward_kinematics.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream::mcap {

namespace {

constexpr char kProbeSchema[] = R"json({
  "title": "mbstream probe report",
  "description": "A viewer's probe position for one frame (probes.csv's row): SI units, the probe's Refer frame",
  "type": "object",
  "properties": {
    "seq": {"type": "integer", "description": "the frame's sequence number"},
    "t": {"type": "number", "description": "simulated time, s"},
    "name": {"type": "string", "description": "the probe's name in the scene script"},
    "x": {"type": "number", "description": "m"},
    "y": {"type": "number", "description": "m"},
    "z": {"type": "number", "description": "m"},
    "latency_us": {"type": "integer", "description": "frame sent to probe received, us; -1 unknown"}
  },
  "required": ["seq", "t", "name", "x", "y", "z", "latency_us"]
})json";

constexpr char kStatsSchema[] = R"json({
  "title": "mbstream run statistics",
  "description": "The run's stats.json: formulation, solver statistics, accuracy figures, status (README.md, results directory)",
  "type": "object"
})json";

// builtin_interfaces/Time's int32 seconds end in January 2038.
constexpr double kLastStampSeconds = 2147483647.0;

void SetPose(Transform& transform, const Pose& X) {
  const Eigen::Quaterniond rotation(X.R);
  for (int i = 0; i < 3; ++i) transform.translation[i] = X.p[i];
  transform.rotation[0] = rotation.x();
  transform.rotation[1] = rotation.y();
  transform.rotation[2] = rotation.z();
  transform.rotation[3] = rotation.w();
}

bool IsBodyOrBase(const Model& model, const std::string& name) {
  return name == model.base_name || model.FindBody(name) >= 0;
}

}  // namespace

std::uint64_t ParseStartTime(const std::string& text, const std::string& flag) {
  int year = 0, month = 0, day = 0, hour = 0, minute = 0;
  double second = 0;
  char zone = 0;
  int used = 0;
  const auto bad = [&] {
    return InputError(FormatString(
        "%s \"%s\": give a UTC time as 2026-11-26T12:00:00Z (fractions of a second allowed) "
        "or seconds since the Unix epoch (1970 to 2038, ROS 2's int32 stamps)",
        flag.c_str(), text.c_str()));
  };
  if (std::sscanf(text.c_str(), "%d-%d-%dT%d:%d:%lf%c%n", &year, &month, &day, &hour, &minute,
                  &second, &zone, &used) == 7) {
    if (zone != 'Z' || used != static_cast<int>(text.size()) || month < 1 || month > 12 ||
        day < 1 || day > 31 || hour > 23 || minute > 59 || second < 0 || second >= 61 ||
        year < 1970) {
      throw bad();
    }
    const std::chrono::year_month_day date{std::chrono::year{year}, std::chrono::month(month),
                                           std::chrono::day(day)};
    if (!date.ok()) throw bad();  // 2026-02-30
    const std::chrono::sys_days days{date};
    const double whole = std::floor(second);
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        days.time_since_epoch() + std::chrono::hours(hour) +
                        std::chrono::minutes(minute) + std::chrono::seconds(long(whole)))
                        .count() +
                    std::llround((second - whole) * 1e9);
    if (ns < 0 || ns >= static_cast<long long>(kLastStampSeconds) * 1000000000) throw bad();
    return static_cast<std::uint64_t>(ns);
  }
  char* end = nullptr;
  const double seconds = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(seconds) || seconds < 0 ||
      seconds >= kLastStampSeconds) {
    throw bad();
  }
  const double whole = std::floor(seconds);
  return static_cast<std::uint64_t>(whole) * 1000000000u +
         static_cast<std::uint64_t>(std::llround((seconds - whole) * 1e9));
}

std::uint64_t NowNanoseconds() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count());
}

RunMcapWriter::RunMcapWriter(const std::string& path, const Model& model,
                             const std::string& model_text, const RunMcapOptions& options)
    : RunMcapWriter(std::make_unique<McapFileSink>(path), model, model_text, options) {}

RunMcapWriter::RunMcapWriter(std::unique_ptr<McapSink> sink, const Model& model,
                             const std::string& model_text, const RunMcapOptions& options)
    : model_(model),
      options_(options),
      writer_(std::move(sink), McapWriterOptions{.compression = options.compression,
                                                 .chunk_size = options.chunk_size,
                                                 .profile = "ros2",
                                                 .library = "mbstream " MBSTREAM_VERSION}),
      data_(model),
      q_(Eigen::VectorXd::Zero(model.nq())) {
  const std::uint16_t joint_state =
      writer_.AddSchema(kJointStateName, "ros2msg", kJointStateDefinition);
  const std::uint16_t tf_message =
      writer_.AddSchema(kTfMessageName, "ros2msg", kTfMessageDefinition);
  const std::uint16_t string = writer_.AddSchema(kStringName, "ros2msg", kStringDefinition);
  const std::uint16_t probe = writer_.AddSchema("mbstream/ProbeReport", "jsonschema", kProbeSchema);
  const std::uint16_t stats = writer_.AddSchema("mbstream/RunStats", "jsonschema", kStatsSchema);
  const std::uint16_t robot_description = writer_.AddChannel(string, "/robot_description", "cdr");
  const std::uint16_t tf_static = writer_.AddChannel(tf_message, "/tf_static", "cdr");
  joint_states_ = writer_.AddChannel(joint_state, "/joint_states", "cdr");
  tf_ = writer_.AddChannel(tf_message, "/tf", "cdr");
  probes_ = writer_.AddChannel(probe, "/mbstream/probes", "json");
  stats_ = writer_.AddChannel(stats, "/mbstream/stats", "json");

  const RosTime start = RosTime::FromNanoseconds(options_.start_time_ns);
  EncodeString(message_, model_text);
  writer_.Write(robot_description, options_.start_time_ns, message_);

  // The links fixed to a body (or the base) and the named points: their poses never change.
  for (const Frame& frame : model_.frames) {
    if (IsBodyOrBase(model_, frame.name)) continue;
    Transform& transform = transforms_.emplace_back();
    transform.frame_id = frame.body == kBase ? model_.base_name : model_.bodies[frame.body].name;
    transform.child_frame_id = frame.name;
    SetPose(transform, frame.X_BF);
  }
  EncodeTfMessage(message_, start, transforms_);
  writer_.Write(tf_static, options_.start_time_ns, message_);

  // /tf: one transform per body, the same names every frame.
  transforms_.clear();
  for (const Body& body : model_.bodies) {
    Transform& transform = transforms_.emplace_back();
    transform.frame_id = body.parent == kBase ? model_.base_name : model_.bodies[body.parent].name;
    transform.child_frame_id = body.name;
  }
}

std::uint64_t RunMcapWriter::LogTime(double t) const {
  // Simulated times are >= 0; a time before the start would wrap, so it is held at the start.
  const double ns = std::round(t * 1e9);
  return options_.start_time_ns + (ns > 0 ? static_cast<std::uint64_t>(ns) : 0);
}

void RunMcapWriter::OnFrame(const RunResult& result, int frame) {
  const std::size_t n = static_cast<std::size_t>(result.num_dofs);
  const std::size_t positions = static_cast<std::size_t>(result.positions());
  const std::uint64_t log_time = LogTime(result.t[frame]);
  const RosTime stamp = RosTime::FromNanoseconds(log_time);
  const double* q = result.q.data() + frame * positions;
  const double* qd = result.qd.data() + frame * n;
  const double* tau = result.has_torques ? result.tau.data() + frame * n : nullptr;
  if (result.num_positions == 0) {
    EncodeJointState(message_, stamp, result.joint_names, q, qd, n, tau, tau ? n : 0);
  } else {
    if (joint_state_names_.empty() && joint_state_velocity_.empty()) {
      for (std::size_t k = 0; k < n; ++k) {
        if (result.position_index[k] < 0) continue;  // a free joint's coordinate
        joint_state_names_.push_back(result.joint_names[k]);
        joint_state_velocity_.push_back(static_cast<int>(k));
        joint_state_position_.push_back(result.position_index[k]);
      }
      joint_state_values_.resize(3 * joint_state_names_.size());
    }
    const std::size_t m = joint_state_names_.size();
    double* values = joint_state_values_.data();
    for (std::size_t j = 0; j < m; ++j) {
      values[j] = q[joint_state_position_[j]];
      values[m + j] = qd[joint_state_velocity_[j]];
      values[2 * m + j] = tau ? tau[joint_state_velocity_[j]] : 0.0;
    }
    EncodeJointState(message_, stamp, joint_state_names_, values, values + m, m,
                     tau ? values + 2 * m : nullptr, tau ? m : 0);
  }
  writer_.Write(joint_states_, log_time, message_);

  // The tree's own coordinates come first (a closed loop's cut joints follow them).
  for (int i = 0; i < model_.nq(); ++i) q_[i] = q[i];
  BodyKinematics(model_, data_, q_);
  for (std::size_t i = 0; i < model_.bodies.size(); ++i) SetPose(transforms_[i], data_.X_parent[i]);
  EncodeTfMessage(message_, stamp, transforms_);
  writer_.Write(tf_, log_time, message_);
  ++frames_;
}

void RunMcapWriter::Finish(const std::vector<ProbeRecord>& probes, const std::string& stats_json,
                           double t_end) {
  for (const ProbeRecord& probe : probes) {
    const nlohmann::json report = {{"seq", probe.seq},
                                   {"t", probe.t},
                                   {"name", probe.name},
                                   {"x", probe.x},
                                   {"y", probe.y},
                                   {"z", probe.z},
                                   {"latency_us", probe.latency_us}};
    writer_.Write(probes_, LogTime(probe.t), report.dump());
  }
  if (!stats_json.empty()) writer_.Write(stats_, LogTime(t_end), stats_json);
  writer_.Close();
}

}  // namespace mbstream::mcap
