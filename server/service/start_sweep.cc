// StartSweep: a parameter sweep stored whole and fed by the server (RunSweeps::Start,
// server/runs/sweep_feeder.h): this call checks it, stores it and queues its first window.
#include "server/runs/request_error.h"
#include "server/service/simulation_service.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// The sweep as the store keeps it (v1.SweepDefinition: the request's fields, wire for wire).
v1::SweepDefinition DefinitionOf(const v1::StartSweepRequest& request) {
  v1::SweepDefinition definition;
  *definition.mutable_base() = request.base();
  for (const v1::SweepAxis& axis : request.grid()) {
    v1::SweepDefinition::Axis& stored = *definition.add_grid();
    stored.set_path(axis.path());
    stored.mutable_values()->CopyFrom(axis.values());
  }
  definition.mutable_list_paths()->CopyFrom(request.list_paths());
  for (const v1::SweepPoint& point : request.list()) {
    definition.add_list()->mutable_values()->CopyFrom(point.values());
  }
  return definition;
}

}  // namespace

grpc::Status SimulationService::StartSweep(grpc::ServerContext* context,
                                           const v1::StartSweepRequest* request,
                                           v1::StartSweepResponse* response) {
  return Admit(*context, "StartSweep", [&]() -> grpc::Status {
    // A client of before the server fed sweeps starts later slices: the server has them all.
    if (!request->sweep_id().empty() || request->first_point() > 0) {
      throw RequestError(RequestErrorKind::kFailedPrecondition,
                         "the server feeds a sweep's points itself (StartSweep once, then "
                         "follow it with GetSweep); sweep " +
                             request->sweep_id().substr(0, 80) + " needs no later slice");
    }
    if (request->max_runs() < 0 || request->window() < 0) {
      throw InputError("window is " +
                       std::to_string(std::min(request->window(), request->max_runs())) +
                       "; give the most runs of the sweep queued at once, or 0 for 32");
    }
    // An older client's first slice: its size is the window.
    const int window = request->window() > 0 ? request->window() : request->max_runs();
    RunSweeps::Started started = runs_->sweeps().Start(request->model(), DefinitionOf(*request),
                                                       window, authorizer_->CallerId(*context));
    response->set_sweep_id(started.id);
    for (const std::string& path : started.paths) response->add_paths(path);
    for (size_t i = 0; i < started.runs.size(); ++i) {
      v1::SweepPoint& point = *response->add_points();
      for (const std::string& value : started.values[i]) point.add_values(value);
      *response->add_runs() = std::move(started.runs[i]);
    }
    response->set_total_points(started.total_points);
    response->set_next_point(started.total_points);  // an older client starts no more slices
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
