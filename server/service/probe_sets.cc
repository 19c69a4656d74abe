// SimulationService::ListProbeSets: the probe sets of a stored run's replays.
#include "server/service/simulation_service.h"

namespace mbstream {

grpc::Status SimulationService::ListProbeSets(grpc::ServerContext* context,
                                              const v1::ListProbeSetsRequest* request,
                                              v1::ListProbeSetsResponse* response) {
  return Admit(*context, "ListProbeSets", [&]() -> grpc::Status {
    for (v1::ProbeSet& set : runs_->ListProbeSets(request->run_id())) {
      *response->add_sets() = std::move(set);
    }
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
