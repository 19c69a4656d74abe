// The Simulation gRPC service (proto/mbstream/v1/simulation_service.proto): translates
// between messages and the model registry / run manager, and maps errors to status codes.
#pragma once

#include <atomic>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/runs/model_registry.h"
#include "server/runs/retention.h"
#include "server/runs/run_deleter.h"
#include "server/runs/run_manager.h"
#include "server/service/authorizer.h"
#include "server/service/live_streams.h"
#include "server/service/peer_channels.h"
#include "server/service/rpc_roles.h"
#include "server/service/status_from_exception.h"
#include "server/service/storage_keeper.h"
#include "server/service/stream_pump.h"

namespace mbstream {

// What serves the data calls (data_rpcs.cc); none is owned.
struct DataKeeping {
  const RunDeleter* deleter = nullptr;
  const Retention* retention = nullptr;
  const StorageKeeper* storage = nullptr;  // GetStorage, BackupStorage (data_rpcs.cc)
};

// Subscribe, WatchRun and Control are reactors on gRPC's callback API (subscribe_call.h,
// watch_call.h, control_call.h); the other methods are synchronous handlers.
class SimulationService final
    : public v1::Simulation::WithCallbackMethod_Control<v1::Simulation::WithCallbackMethod_WatchRun<
          v1::Simulation::WithCallbackMethod_Subscribe<v1::Simulation::Service>>> {
 public:
  // None is owned; all must outlive the service. `peers` (a cluster's replicas on a shared
  // store) proxies calls about runs integrating on other replicas; null: none are proxied.
  // `data` serves DeleteRuns, DeleteModel, SetKeep and RetentionPlan; without: UNIMPLEMENTED.
  SimulationService(ModelRegistry* models, RunManager* runs, const Authorizer* authorizer,
                    PeerChannels* peers = nullptr, DataKeeping data = {});

  grpc::Status SubmitModel(grpc::ServerContext* context, const v1::SubmitModelRequest* request,
                           v1::ModelInfo* response) override;
  grpc::Status ListModels(grpc::ServerContext* context, const v1::ListModelsRequest* request,
                          v1::ListModelsResponse* response) override;
  grpc::Status GetModel(grpc::ServerContext* context, const v1::GetModelRequest* request,
                        v1::GetModelResponse* response) override;
  grpc::Status StartRun(grpc::ServerContext* context, const v1::StartRunRequest* request,
                        v1::RunInfo* response) override;
  grpc::Status StartRuns(grpc::ServerContext* context, const v1::StartRunsRequest* request,
                         v1::StartRunsResponse* response) override;
  grpc::Status StartSweep(grpc::ServerContext* context, const v1::StartSweepRequest* request,
                          v1::StartSweepResponse* response) override;  // start_sweep.cc
  grpc::Status CancelRun(grpc::ServerContext* context, const v1::CancelRunRequest* request,
                         v1::RunInfo* response) override;
  grpc::Status GetRun(grpc::ServerContext* context, const v1::GetRunRequest* request,
                      v1::RunInfo* response) override;
  grpc::Status ListRuns(grpc::ServerContext* context, const v1::ListRunsRequest* request,
                        v1::ListRunsResponse* response) override;
  grpc::Status GetResult(grpc::ServerContext* context, const v1::GetResultRequest* request,
                         grpc::ServerWriter<v1::ResultChunk>* writer) override;  // get_result.cc
  grpc::Status GetResults(grpc::ServerContext* context, const v1::GetResultsRequest* request,
                          grpc::ServerWriter<v1::ResultChunk>* writer) override;  // get_result.cc
  grpc::Status ListProbeSets(grpc::ServerContext* context, const v1::ListProbeSetsRequest* request,
                             v1::ListProbeSetsResponse* response) override;  // replay_rpcs.cc
  grpc::Status ReplayRun(grpc::ServerContext* context, const v1::ReplayRunRequest* request,
                         v1::RunInfo* response) override;  // replay_rpcs.cc
  grpc::ServerWriteReactor<v1::WatchEvent>* WatchRun(
      grpc::CallbackServerContext* context,
      const v1::WatchRunRequest* request) override;  // watch_call.h
  grpc::ServerBidiReactor<v1::SubscribeRequest, v1::SubscribeEvent>* Subscribe(
      grpc::CallbackServerContext* context) override;  // subscribe_call.h
  grpc::ServerBidiReactor<v1::ControlRequest, v1::ControlResponse>* Control(
      grpc::CallbackServerContext* context) override;  // control_call.h
  grpc::Status DeleteRuns(grpc::ServerContext* context, const v1::DeleteRunsRequest* request,
                          v1::DeleteRunsResponse* response) override;  // data_rpcs.cc
  grpc::Status DeleteModel(grpc::ServerContext* context, const v1::DeleteModelRequest* request,
                           v1::DeleteModelResponse* response) override;  // data_rpcs.cc
  grpc::Status SetKeep(grpc::ServerContext* context, const v1::SetKeepRequest* request,
                       v1::RunInfo* response) override;  // data_rpcs.cc
  grpc::Status RetentionPlan(grpc::ServerContext* context, const v1::RetentionPlanRequest* request,
                             v1::RetentionPlanResponse* response) override;  // data_rpcs.cc
  grpc::Status GetSweep(grpc::ServerContext* context, const v1::GetSweepRequest* request,
                        v1::SweepProgress* response) override;  // sweep_rpcs.cc
  grpc::Status CancelSweep(grpc::ServerContext* context, const v1::CancelSweepRequest* request,
                           v1::SweepProgress* response) override;  // sweep_rpcs.cc

  grpc::Status ExportMcap(
      grpc::ServerContext* context, const v1::ExportMcapRequest* request,
      grpc::ServerWriter<v1::McapFileChunk>* writer) override;  // export_mcap.cc
  grpc::Status GetStorage(grpc::ServerContext* context, const v1::GetStorageRequest* request,
                          v1::GetStorageResponse* response) override;  // data_rpcs.cc
  grpc::Status BackupStorage(grpc::ServerContext* context, const v1::BackupStorageRequest* request,
                             v1::BackupStorageResponse* response) override;  // data_rpcs.cc

  // Ends every stream at its next event (shutdown).
  void Stop() {
    stopping_ = true;
    live_.PokeAll();
  }

 private:
  // The gate of every handler: the caller's token must have the role kRpcRoles gives
  // `method`; then `body` runs, its exceptions mapped to status codes.
  template <typename Body>
  grpc::Status Admit(const grpc::ServerContext& context, std::string_view method, Body body) {
    if (grpc::Status denied = authorizer_->Check(context, RoleOf(method)); !denied.ok()) {
      return denied;
    }
    return Serve(body);
  }

  // GetResult's wait: until run `run_id` has ended (OK, `ended` gets its final info), the
  // client is gone (CANCELLED) or the server stops (UNAVAILABLE). get_result.cc.
  grpc::Status AwaitEnd(const grpc::ServerContext& context, const std::string& run_id,
                        v1::RunInfo* ended);

  // One run's result onto `writer` (GetResult's body; GetResults sends several). Adds the
  // frames' and probes' bytes sent to `sent_bytes`. get_result.cc.
  grpc::Status SendResult(grpc::ServerContext& context, const std::string& run_id,
                          const std::string& probe_set, bool wait,
                          grpc::ServerWriter<v1::ResultChunk>& writer, size_t& sent_bytes);

  // OK while run `run_id` is stored; NOT_FOUND once it was deleted (a reader may then have
  // read part of it). get_result.cc.
  grpc::Status StillStored(const std::string& run_id) const;

  // ExportMcap's body: the run as MCAP onto `writer`, adding the file's bytes sent to
  // `sent_bytes`. export_mcap.cc.
  grpc::Status SendMcap(grpc::ServerContext& context, const v1::ExportMcapRequest& request,
                        grpc::ServerWriter<v1::McapFileChunk>& writer, size_t& sent_bytes);

  ModelRegistry* models_;
  RunManager* runs_;
  const Authorizer* authorizer_;
  PeerChannels* peers_;
  DataKeeping data_;
  std::atomic<bool> stopping_{false};
  LiveStreams live_;  // the open streaming reactors
  StreamPump pump_;   // after live_ and the rest: its tasks may hold the last of a reactor
};

}  // namespace mbstream
