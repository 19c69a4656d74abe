#include "client/cli/result_mcap.h"

#include <set>

#include "server/mcap/run_mcap.h"
#include "server/parse/model_file.h"
#include "server/parse/sdf_import.h"
#include "server/parse/urdf_import.h"

namespace mbstream::cli {

void CheckResultMcapOptions(const ResultMcapOptions& options) {
  mcap::ParseCompression(options.compression);
  if (!options.start.empty()) mcap::ParseStartTime(options.start, "--mcap-start");
}

grpc::Status WriteResultMcap(v1::Simulation::Stub& stub, const v1::RunInfo& info,
                             const RunResult& result, const std::vector<ProbeRecord>& probes,
                             const std::string& stats_json, const ResultMcapOptions& options) {
  grpc::ClientContext context;
  v1::GetModelRequest request;
  request.set_model(info.model_id());
  request.set_include_bundle(true);
  v1::GetModelResponse model_response;
  const grpc::Status status = stub.GetModel(&context, request, &model_response);
  if (!status.ok()) return status;
  const v1::ModelBundle& bundle = model_response.bundle();
  const std::string source = "model " + info.model_id();
  // The model as the server compiled it (the same reader: the same joint order and links).
  const Model model =
      DetectModelFormat(bundle.urdf()) == ModelFormat::kSdf
          ? ImportSdf(bundle.urdf(), source).model
          : ImportUrdf(bundle.urdf(), source, {}, UrdfImportOptions{.repair = bundle.repair()})
                .model;

  mcap::RunMcapOptions mcap_options;
  mcap_options.compression = mcap::ParseCompression(options.compression);
  mcap_options.start_time_ns = !options.start.empty()
                                   ? mcap::ParseStartTime(options.start, "--mcap-start")
                                   : static_cast<std::uint64_t>(info.started_unix_ms()) * 1000000u;
  mcap::RunMcapWriter writer(options.path, model, bundle.urdf(), mcap_options);
  for (int frame = 0; frame < result.num_frames(); ++frame) writer.OnFrame(result, frame);
  writer.Finish(probes, stats_json, result.stats.t_reached);
  return grpc::Status::OK;
}

}  // namespace mbstream::cli
