// The run spec at the server's edge: protobuf's JSON mapping of mbstream.v1.RunSpec in and
// out, and its validated conversion to and from the physics core's RunConfig. The core
// never sees generated code; this is the only place that translates.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/run_spec.pb.h"
#include "server/sim/run_config.h"

namespace mbstream {

// Parses protobuf's JSON mapping of mbstream.v1.RunSpec (field names as in the proto or in
// lowerCamelCase; unknown fields are an error). `source` names the text in messages.
// Throws InputError: "<source>: invalid JSON/RunSpec: <protobuf's message>; see
// models/irb1600/seed-run.json for an example".
v1::RunSpec ParseRunSpecJson(const std::string& json, const std::string& source);

// Reads and parses the JSON file at `path`. Throws InputError naming the path when the file
// cannot be read or does not parse.
v1::RunSpec LoadRunSpecFile(const std::string& path);

// Validates `spec` for a model whose joints are `joint_names` (in the model's order) and
// converts it to the core's RunConfig, applying the defaults of absent fields (duration
// 20 s, output interval 0.05 s, rtol 1e-6, atol 1e-8, gravity (0, 0, -9.81) m/s^2 (callers
// take an SDF world's <gravity> instead when the spec gives none), fixed
// step 1e-3 s, want_torques true). The result has one drive per joint; joints without a
// Drive are passive. Throws InputError "<source>: <field path>: <problem>; <what to do>".
// RunSpec.realtime and RunSpec.max_output_frames are checked but are not part of RunConfig.
RunConfig ToRunConfig(const v1::RunSpec& spec, const std::vector<std::string>& joint_names,
                      const std::string& source);

// The coordinates a spec's vectors refer to: initial_q has one value per position, initial_qd
// and the drives one per velocity. They differ only for a model with free joints (7 positions,
// 6 velocities each: server/model/coordinate_names.h); the overload above gives joint_names
// for both.
struct SpecCoordinates {
  std::vector<std::string> positions;
  std::vector<std::string> velocities;
};
RunConfig ToRunConfig(const v1::RunSpec& spec, const SpecCoordinates& coordinates,
                      const std::string& source);

// The reverse, for recording the spec a run used: every field set explicitly, drives by
// position (no joint names), one per entry of config.drives.
v1::RunSpec ToRunSpec(const RunConfig& config);

// Prints `spec` with protobuf's JSON printer: indented, field names as in the proto, fields
// with default values included.
std::string RunSpecToJson(const v1::RunSpec& spec);

}  // namespace mbstream
