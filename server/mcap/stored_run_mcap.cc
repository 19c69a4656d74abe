#include "server/mcap/stored_run_mcap.h"

#include "server/spec/run_spec_json.h"
#include "server/wire/frame_conversion.h"
#include "shared/common/check.h"

namespace mbstream::mcap {

RunProvenance StoredRunProvenance(const v1::RunInfo& info) {
  SpecCoordinates coordinates;
  coordinates.velocities.assign(info.joint_names().begin(), info.joint_names().end());
  coordinates.positions =
      info.position_names().empty()
          ? coordinates.velocities
          : std::vector<std::string>(info.position_names().begin(), info.position_names().end());
  std::string spec_json;
  try {
    spec_json = RunSpecToJson(ToRunSpec(ToRunConfig(info.spec(), coordinates, "spec")));
  } catch (const std::exception&) {
    spec_json = RunSpecToJson(info.spec());
  }
  return RunProvenance{info.model_name(), "model " + info.model_id(), spec_json, info.model_id(),
                       info.id()};
}

ProbeRecord ProbeRecordFromProto(const v1::ProbeReport& p) {
  return {
      p.seq(),       p.t_s(), p.probe(), p.position_m().x(), p.position_m().y(), p.position_m().z(),
      p.latency_us()};
}

RunMcapOptions StoredRunMcapOptions(const v1::RunInfo& info, const std::string& compression,
                                    const std::string& start, const std::string& flag_prefix) {
  RunMcapOptions options;
  options.compression = ParseCompression(compression.empty() ? "zstd" : compression);
  options.start_time_ns = !start.empty()
                              ? ParseStartTime(start, flag_prefix + "start")
                              : static_cast<std::uint64_t>(info.started_unix_ms()) * 1000000u;
  return options;
}

StoredRunMcapWriter::StoredRunMcapWriter(std::unique_ptr<McapSink> sink, const v1::RunInfo& info,
                                         const Model& model, const std::string& model_text,
                                         const RunMcapOptions& options)
    : info_(info), writer_(std::move(sink), model, model_text, options) {}

void StoredRunMcapWriter::AddFrames(const std::vector<std::string_view>& frames) {
  batch_.resize(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (!batch_[i].ParseFromArray(frames[i].data(), static_cast<int>(frames[i].size()))) {
      throw InputError("run " + info_.id() + ": stored frame " +
                       std::to_string(writer_.frames() + static_cast<long>(i)) +
                       " is not a Frame; the result is corrupt, run it again");
    }
  }
  const RunResult result = ResultFromFrames(info_, batch_);
  for (int frame = 0; frame < result.num_frames(); ++frame) writer_.OnFrame(result, frame);
}

void StoredRunMcapWriter::Finish(const std::vector<v1::ProbeReport>& probes) {
  std::vector<ProbeRecord> records;
  records.reserve(probes.size());
  for (const v1::ProbeReport& probe : probes) records.push_back(ProbeRecordFromProto(probe));
  const RunResult result = ResultFromFrames(info_, {});
  const std::string stats = StatsJson(result, StoredRunProvenance(info_), writer_.frames());
  writer_.Finish(records, stats, result.stats.t_reached);
}

}  // namespace mbstream::mcap
