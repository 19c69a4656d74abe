#include "client/cli/result_mcap.h"

#include "server/mcap/mcap_compression.h"
#include "server/mcap/mcap_sink.h"
#include "server/mcap/run_mcap.h"

namespace mbstream::cli {

void CheckResultMcapOptions(const ResultMcapOptions& options) {
  mcap::ParseCompression(options.compression);
  if (!options.start.empty()) mcap::ParseStartTime(options.start, "--mcap-start");
}

grpc::Status SaveResultMcap(v1::Simulation::Stub& stub, const std::string& run_id,
                            const std::string& probe_set, bool wait,
                            const ResultMcapOptions& options, v1::RunInfo* info) {
  grpc::ClientContext context;
  v1::ExportMcapRequest request;
  request.set_run_id(run_id);
  request.set_probe_set(probe_set);
  request.set_compression(options.compression);
  request.set_start(options.start);
  request.set_wait(wait);
  std::unique_ptr<grpc::ClientReader<v1::McapFileChunk>> reader =
      stub.ExportMcap(&context, request);
  mcap::McapFileSink file(options.path);  // removed unless closed
  v1::McapFileChunk chunk;
  while (reader->Read(&chunk)) {
    if (chunk.has_info()) *info = chunk.info();
    file.Write(chunk.data());
  }
  grpc::Status status = reader->Finish();
  if (status.ok()) file.Close();
  return status;
}

}  // namespace mbstream::cli
