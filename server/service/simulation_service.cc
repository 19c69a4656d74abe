#include "server/service/simulation_service.h"

#include <spdlog/spdlog.h>

#include "server/parse/import_cancel.h"
#include "server/runs/request_error.h"
#include "server/service/peer_proxy.h"
#include "server/service/status_from_exception.h"
#include "shared/common/check.h"

namespace mbstream {

SimulationService::SimulationService(ModelRegistry* models, RunManager* runs,
                                     const Authorizer* authorizer, PeerChannels* peers,
                                     DataKeeping data)
    : models_(models), runs_(runs), authorizer_(authorizer), peers_(peers), data_(data) {
  MBSTREAM_CHECK(models_ != nullptr && runs_ != nullptr && authorizer_ != nullptr);
}

grpc::Status SimulationService::SubmitModel(grpc::ServerContext* context,
                                            const v1::SubmitModelRequest* request,
                                            v1::ModelInfo* response) {
  const grpc::Status status = Admit(*context, "SubmitModel", [&]() -> grpc::Status {
    // A caller gone abandons the import (ImportCancelled: UNAVAILABLE, nothing stored).
    const ImportCancelScope cancel_scope([context] { return context->IsCancelled(); });
    spdlog::debug("SubmitModel: importing a bundle of {} bytes", request->ByteSizeLong());
    *response = models_->Submit(request->bundle(), false);
    return grpc::Status::OK;
  });
  runs_->results().ReleaseMemory();  // a bundle of many MiB passed through (its received slices)
  return status;
}

grpc::Status SimulationService::ListModels(grpc::ServerContext* context,
                                           const v1::ListModelsRequest*,
                                           v1::ListModelsResponse* response) {
  return Admit(*context, "ListModels", [&]() -> grpc::Status {
    runs_->replica().RefreshModels();  // models submitted to other replicas (a shared store)
    for (const v1::ModelInfo& info : models_->List()) *response->add_models() = info;
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::GetModel(grpc::ServerContext* context,
                                         const v1::GetModelRequest* request,
                                         v1::GetModelResponse* response) {
  return Admit(*context, "GetModel", [&]() -> grpc::Status {
    *response->mutable_info() = runs_->replica().ModelInfo(request->model());
    if (request->include_bundle()) {
      *response->mutable_bundle() = models_->Bundle(response->info().id());
    }
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::StartRun(grpc::ServerContext* context,
                                         const v1::StartRunRequest* request,
                                         v1::RunInfo* response) {
  return Admit(*context, "StartRun", [&]() -> grpc::Status {
    *response = runs_->Start(request->model(), request->spec(), authorizer_->CallerId(*context));
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::StartRuns(grpc::ServerContext* context,
                                          const v1::StartRunsRequest* request,
                                          v1::StartRunsResponse* response) {
  return Admit(*context, "StartRuns", [&]() -> grpc::Status {
    for (v1::RunInfo& info :
         runs_->StartMany(request->model(), request->specs(), authorizer_->CallerId(*context))) {
      *response->add_runs() = std::move(info);
    }
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::CancelRun(grpc::ServerContext* context,
                                          const v1::CancelRunRequest* request,
                                          v1::RunInfo* response) {
  return Admit(*context, "CancelRun", [&]() -> grpc::Status {
    const v1::RunInfo info = runs_->Get(request->run_id());  // NOT_FOUND first
    if (!info.owner().empty() && info.owner() != authorizer_->CallerId(*context) &&
        !authorizer_->CallerHas(*context, Role::kAdmin)) {
      return grpc::Status(grpc::StatusCode::PERMISSION_DENIED,
                          "run " + info.id() +
                              " was started with another token; only that token or an admin "
                              "token may cancel it");
    }
    const bool forwards = peers_ != nullptr && !PeerChannels::IsProxied(*context);
    // A run queued in the shared store when located may be claimed by another replica before
    // Cancel ends it (Cancel then refuses: it integrates there): located again, the cancel is
    // forwarded there. A run is claimed once; the third look covers a hand-back (drain).
    for (int look = 0;; ++look) {
      if (forwards) {
        if (ReplicaControl::RunPlace place = runs_->replica().Locate(info.id());
            place.where == ReplicaControl::RunPlace::Where::kElsewhere) {
          return ProxyCancelRun(*peers_, *context, *request, place.info, response);
        }
      }
      try {
        *response = runs_->Cancel(request->run_id());
        return grpc::Status::OK;
      } catch (const RequestError& error) {
        if (!forwards || error.kind() != RequestErrorKind::kFailedPrecondition || look == 2) throw;
      }
    }
  });
}

grpc::Status SimulationService::GetRun(grpc::ServerContext* context,
                                       const v1::GetRunRequest* request, v1::RunInfo* response) {
  return Admit(*context, "GetRun", [&]() -> grpc::Status {
    *response = runs_->Get(request->run_id());
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::ListRuns(grpc::ServerContext* context,
                                         const v1::ListRunsRequest* request,
                                         v1::ListRunsResponse* response) {
  return Admit(*context, "ListRuns", [&]() -> grpc::Status {
    RunManager::RunPage page = runs_->List(request->model(), request->limit(), request->page_size(),
                                           request->page_token());
    for (v1::RunInfo& info : page.runs) *response->add_runs() = std::move(info);
    response->set_next_page_token(page.next_page_token);
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
