// A run as one MCAP file that ROS 2 tools, Foxglove and PlotJuggler open (docs/mcap.md):
//   /joint_states        sensor_msgs/msg/JointState, one per frame (CDR, schema ros2msg)
//   /tf                  tf2_msgs/msg/TFMessage, one per frame: each body's pose in its parent
//   /tf_static           tf2_msgs/msg/TFMessage, once: the fixed links and named points
//   /robot_description   std_msgs/msg/String, once: the model's URDF or SDFormat text
//   /mbstream/probes     the viewer's probe reports, JSON (schema: jsonschema)
//   /mbstream/stats      stats.json, once, at the last frame's time (JSON, jsonschema)
// Stamps and log times are the start time plus the simulated time, in ns. Frames are
// written as they come (a FrameSink), so memory is one chunk, not the run.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "server/mcap/mcap_writer.h"
#include "server/mcap/ros_messages.h"
#include "server/model/data.h"
#include "server/model/model.h"
#include "server/results/results_files.h"
#include "server/sim/run_result.h"

namespace mbstream::mcap {

struct RunMcapOptions {
  Compression compression = Compression::kZstd;
  std::size_t chunk_size = 1 << 20;
  std::uint64_t start_time_ns = 0;  // the time of t = 0, ns since the Unix epoch (UTC)
};

// ns since the Unix epoch from "2026-11-26T12:00:00Z" (UTC; fractions of a second allowed)
// or a number of seconds since the epoch ("1764158400.5"). Throws InputError naming `flag`.
std::uint64_t ParseStartTime(const std::string& text, const std::string& flag);

// Now, in ns since the Unix epoch.
std::uint64_t NowNanoseconds();

class RunMcapWriter : public FrameSink {
 public:
  // `model` must outlive the writer. Writes /robot_description and /tf_static at once.
  RunMcapWriter(const std::string& path, const Model& model, const std::string& model_text,
                const RunMcapOptions& options);
  // The same into `sink` (the server's ExportMcap streams the bytes to its client).
  RunMcapWriter(std::unique_ptr<McapSink> sink, const Model& model, const std::string& model_text,
                const RunMcapOptions& options);

  void OnFrame(const RunResult& result, int frame) override;
  bool KeepsFrames() const override { return true; }

  // Writes the probe reports and stats.json's text (`stats_json`, "" for none) and closes the
  // file (or the sink). Throws the sink's error when it cannot be written.
  void Finish(const std::vector<ProbeRecord>& probes, const std::string& stats_json, double t_end);

  long frames() const { return frames_; }
  std::uint64_t bytes_written() const { return writer_.bytes_written(); }

 private:
  std::uint64_t LogTime(double t) const;

  const Model& model_;
  RunMcapOptions options_;
  McapWriter writer_;
  std::uint16_t joint_states_ = 0, tf_ = 0, probes_ = 0, stats_ = 0;
  Data data_;
  Eigen::VectorXd q_;  // the tree's positions (model.nq())
  // With free bodies: /joint_states holds the one-coordinate joints only (a free body's pose
  // is in /tf, as a ROS floating base is): their names, positions, velocities and efforts,
  // gathered per frame into these (sized at the first frame).
  std::vector<std::string> joint_state_names_;
  std::vector<int> joint_state_velocity_, joint_state_position_;
  std::vector<double> joint_state_values_;
  std::vector<Transform> transforms_;
  std::string message_;
  long frames_ = 0;
};

}  // namespace mbstream::mcap
