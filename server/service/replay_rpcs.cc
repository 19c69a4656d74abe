// SimulationService::ListProbeSets (the probe sets of a stored run's replays) and ReplayRun
// (a stored run streamed to the followers as if it were running).
#include "server/service/simulation_service.h"

namespace mbstream {

grpc::Status SimulationService::ListProbeSets(grpc::ServerContext* context,
                                              const v1::ListProbeSetsRequest* request,
                                              v1::ListProbeSetsResponse* response) {
  return Admit(*context, "ListProbeSets", [&]() -> grpc::Status {
    for (v1::ProbeSet& set : runs_->replays().ProbeSets(request->run_id())) {
      *response->add_sets() = std::move(set);
    }
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::ReplayRun(grpc::ServerContext* context,
                                          const v1::ReplayRunRequest* request,
                                          v1::RunInfo* response) {
  return Admit(*context, "ReplayRun", [&]() -> grpc::Status {
    *response = runs_->replays().ToFollowers(request->run_id(),
                                             request->speed() == 0.0 ? 1.0 : request->speed());
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
