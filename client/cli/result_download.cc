#include "client/cli/result_download.h"

#include <vector>

#include "server/results/results_files.h"
#include "server/spec/run_spec_json.h"
#include "server/wire/frame_conversion.h"

namespace mbstream::cli {

grpc::Status DownloadResult(v1::Simulation::Stub& stub, const std::string& run_id,
                            const std::string& directory, v1::RunInfo* info,
                            const std::string& probe_set, const ResultMcapOptions* mcap,
                            bool wait) {
  grpc::ClientContext context;
  v1::GetResultRequest request;
  request.set_run_id(run_id);
  request.set_probe_set(probe_set);
  request.set_wait(wait);
  std::unique_ptr<grpc::ClientReader<v1::ResultChunk>> reader = stub.GetResult(&context, request);
  v1::ResultChunk chunk;
  std::vector<v1::Frame> frames;
  std::vector<ProbeRecord> probes;
  while (reader->Read(&chunk)) {
    if (chunk.has_info()) *info = chunk.info();
    for (v1::Frame& frame : *chunk.mutable_frames()) frames.push_back(std::move(frame));
    for (const v1::ProbeReport& p : chunk.probes()) {
      probes.push_back({p.seq(), p.t_s(), p.probe(), p.position_m().x(), p.position_m().y(),
                        p.position_m().z(), p.latency_us()});
    }
  }
  grpc::Status status = reader->Finish();
  if (!status.ok()) return status;
  const RunResult result = ResultFromFrames(*info, frames);
  // The spec as the engine saw it (every field explicit), like `mbstream simulate` records.
  std::string spec_json;
  try {
    spec_json = RunSpecToJson(ToRunSpec(ToRunConfig(info->spec(), result.joint_names, "spec")));
  } catch (const std::exception&) {
    spec_json = RunSpecToJson(info->spec());
  }
  const RunProvenance provenance{info->model_name(), "model " + info->model_id(), spec_json,
                                 info->model_id(), info->id()};
  if (!directory.empty()) WriteResultsDirectory(result, provenance, directory, probes);
  if (mcap != nullptr && !mcap->path.empty()) {
    return WriteResultMcap(stub, *info, result, probes, StatsJson(result, provenance), *mcap);
  }
  return grpc::Status::OK;
}

}  // namespace mbstream::cli
