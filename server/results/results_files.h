// Writes a run's results directory (the files README.md lists): joints.csv, velocities.csv,
// tcp.csv, torques.csv (when dynamics ran), energy.csv, probes.csv (when a viewer answered),
// loop_forces.csv (a mechanism with closed loops, report_loop_forces), stats.json. Numbers are
// written in their shortest exact form (std::to_chars: each reads back as the same double), so the
// same run gives bit-identical files.
#pragma once

#include <string>
#include <vector>

#include "server/sim/run_result.h"

namespace mbstream {

// What stats.json records beside the run's statistics, so a run can be reproduced.
struct RunProvenance {
  std::string model_name;
  std::string model_source;  // the URDF file or the model id
  std::string spec_json;     // the run spec as protobuf JSON (empty: omitted)
  std::string model_id;      // the server's content id (empty: omitted)
  std::string run_id;        // the server's run id (empty: omitted)
};

// One probe report of a viewer (probes.csv): the probe's position for frame `seq`.
struct ProbeRecord {
  long long seq = 0;
  double t = 0.0;                    // s, the frame's simulated time
  std::string name;                  // the probe's name in the scene script
  double x = 0.0, y = 0.0, z = 0.0;  // m, in the probe's Refer frame
  long long latency_us = -1;         // us, frame sent -> probe received; -1 = unknown
};

// Writes the files into `directory` (created if missing). Each file is written to a
// temporary name and renamed, so no half-written file is left behind. Throws InputError
// naming the path when the directory cannot be created or written.
// probes.csv (`seq,t,name,x,y,z,latency_us`) is written when `probes` holds any.
void WriteResultsDirectory(const RunResult& result, const RunProvenance& provenance,
                           const std::string& directory,
                           const std::vector<ProbeRecord>& probes = {});

// stats.json's text for a run; `frames` is its frame count when the result holds only the
// latest frame (FrameSink::KeepsFrames), -1 = the result's own count.
std::string StatsJson(const RunResult& result, const RunProvenance& provenance, long frames = -1);

}  // namespace mbstream
