// A stored run as one MCAP file (docs/mcap.md): its RunInfo, its frames as the store keeps them
// (serialized v1::Frame messages, fed to RunMcapWriter one stored chunk at a time, so memory
// is a chunk, not the run) and its probe reports. /mbstream/stats holds stats.json's text as
// `mbstream result --out` writes it. The server's ExportMcap writes it into its stream; the
// CLI's `result --mcap` and the Python client's `Result.to_mcap` save those bytes.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/mcap/run_mcap.h"
#include "server/results/results_files.h"

namespace mbstream::mcap {

// What stats.json records of a stored run: its model and ids, and its spec as the engine saw
// it (every field explicit, as `mbstream simulate` records it).
RunProvenance StoredRunProvenance(const v1::RunInfo& info);

// probes.csv's row of a probe report.
ProbeRecord ProbeRecordFromProto(const v1::ProbeReport& probe);

// The MCAP options of an export: `compression` "zstd" (also when empty), "lz4" or "none";
// `start` the UTC time of t = 0 (ParseStartTime's forms), empty: the run's start
// (RunInfo.started_unix_ms). Throws InputError naming `flag_prefix` + "compression" or
// "start".
RunMcapOptions StoredRunMcapOptions(const v1::RunInfo& info, const std::string& compression,
                                    const std::string& start, const std::string& flag_prefix);

class StoredRunMcapWriter {
 public:
  // `model` (the run's, as the server compiled it) must outlive the writer; `model_text` is its
  // URDF or SDFormat text (/robot_description).
  StoredRunMcapWriter(std::unique_ptr<McapSink> sink, const v1::RunInfo& info, const Model& model,
                      const std::string& model_text, const RunMcapOptions& options);

  // The next frames in sequence order, each a serialized v1::Frame. Throws InputError naming
  // the frame when one is corrupt (not a Frame, or not the run's joint count).
  void AddFrames(const std::vector<std::string_view>& frames);
  // The probe reports, /mbstream/stats, the summary; closes the sink.
  void Finish(const std::vector<v1::ProbeReport>& probes);

  long frames() const { return writer_.frames(); }
  std::uint64_t bytes_written() const { return writer_.bytes_written(); }

 private:
  v1::RunInfo info_;
  RunMcapWriter writer_;
  std::vector<v1::Frame> batch_;
};

}  // namespace mbstream::mcap
