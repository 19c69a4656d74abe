#include "client/cli/result_download.h"

#include <vector>

#include "server/mcap/stored_run_mcap.h"
#include "server/results/results_files.h"
#include "server/wire/frame_conversion.h"

namespace mbstream::cli {

namespace {

grpc::Status DownloadResultFiles(v1::Simulation::Stub& stub, const std::string& run_id,
                                 const std::string& directory, v1::RunInfo* info,
                                 const std::string& probe_set, bool wait) {
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
    for (const v1::ProbeReport& p : chunk.probes()) probes.push_back(mcap::ProbeRecordFromProto(p));
  }
  grpc::Status status = reader->Finish();
  if (!status.ok()) return status;
  if (!directory.empty()) {
    WriteResultsDirectory(ResultFromFrames(*info, frames), mcap::StoredRunProvenance(*info),
                          directory, probes);
  }
  return grpc::Status::OK;
}

}  // namespace

grpc::Status DownloadResult(v1::Simulation::Stub& stub, const std::string& run_id,
                            const std::string& directory, v1::RunInfo* info,
                            const std::string& probe_set, const ResultMcapOptions* mcap,
                            bool wait) {
  // The frames are fetched for the files, or for the info alone (a sweep waiting for its runs);
  // the MCAP file is the server's, saved as it comes.
  const bool with_mcap = mcap != nullptr && !mcap->path.empty();
  if (!directory.empty() || !with_mcap) {
    if (grpc::Status s = DownloadResultFiles(stub, run_id, directory, info, probe_set, wait);
        !s.ok()) {
      return s;
    }
  }
  if (with_mcap) {
    return SaveResultMcap(stub, run_id, probe_set, wait, *mcap, info);
  }
  return grpc::Status::OK;
}

}  // namespace mbstream::cli
