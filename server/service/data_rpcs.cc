// SimulationService::DeleteRuns, DeleteModel, SetKeep and RetentionPlan (run_deleter.h,
// retention.h): what is kept and what is deleted.
#include "server/service/simulation_service.h"

namespace mbstream {

namespace {

grpc::Status NotServed() {
  return grpc::Status(grpc::StatusCode::UNIMPLEMENTED, "this server does not manage its data");
}

}  // namespace

grpc::Status SimulationService::DeleteRuns(grpc::ServerContext* context,
                                           const v1::DeleteRunsRequest* request,
                                           v1::DeleteRunsResponse* response) {
  return Admit(*context, "DeleteRuns", [&]() -> grpc::Status {
    if (data_.deleter == nullptr) return NotServed();
    const std::vector<std::string> ids(request->run_ids().begin(), request->run_ids().end());
    for (v1::RunInfo& info : data_.deleter->DeleteRuns(ids)) {
      *response->add_runs() = std::move(info);
    }
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::DeleteModel(grpc::ServerContext* context,
                                            const v1::DeleteModelRequest* request,
                                            v1::DeleteModelResponse* response) {
  return Admit(*context, "DeleteModel", [&]() -> grpc::Status {
    if (data_.deleter == nullptr) return NotServed();
    std::vector<v1::RunInfo> runs;
    *response->mutable_model() =
        data_.deleter->DeleteModel(request->model(), request->with_runs(), &runs);
    for (v1::RunInfo& info : runs) *response->add_runs() = std::move(info);
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::SetKeep(grpc::ServerContext* context,
                                        const v1::SetKeepRequest* request, v1::RunInfo* response) {
  return Admit(*context, "SetKeep", [&]() -> grpc::Status {
    if (data_.deleter == nullptr) return NotServed();
    *response = data_.deleter->SetKeep(request->run_id(), request->keep());
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::RetentionPlan(grpc::ServerContext* context,
                                              const v1::RetentionPlanRequest*,
                                              v1::RetentionPlanResponse* response) {
  return Admit(*context, "RetentionPlan", [&]() -> grpc::Status {
    if (data_.retention == nullptr) return NotServed();
    const RetentionPolicy& policy = data_.retention->policy();
    response->set_retain_runs(static_cast<int32_t>(policy.retain_runs));
    response->set_retain_days(policy.retain_days);
    for (v1::RunInfo& info : data_.retention->Plan()) *response->add_runs() = std::move(info);
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
