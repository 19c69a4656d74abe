// GetSweep and CancelSweep: a sweep as a whole, from the runs the store holds under its id
// (RunManager::SweepRuns), so that any replica of a cluster answers for every replica's runs.
#include <chrono>

#include "server/runs/request_error.h"
#include "server/service/simulation_service.h"
#include "server/service/sweep_progress.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

namespace {

// How long CancelSweep waits for the sweep's runs to end (a cancelled run ends at its next
// step; a run on an unreachable replica may not).
constexpr auto kCancelWait = std::chrono::seconds(10);

std::vector<v1::RunInfo> KnownSweepRuns(const RunManager& runs, const std::string& sweep_id) {
  std::vector<v1::RunInfo> found = runs.SweepRuns(sweep_id);
  if (found.empty()) {
    throw RequestError(RequestErrorKind::kNotFound,
                       "no run belongs to sweep '" + sweep_id.substr(0, 80) +
                           "'; give the id `mbstream sweep` printed (s-...)");
  }
  return found;
}

// Waits until run `run` has ended or `until` passes; a run deleted meanwhile counts as ended.
void AwaitEnded(const RunManager& runs, v1::RunInfo run,
                std::chrono::steady_clock::time_point until) {
  try {
    while (!IsFinalState(run.state()) && std::chrono::steady_clock::now() < until) {
      run = runs.AwaitChange(run.id(), run.state(), until);
    }
  } catch (const RequestError& error) {
    if (error.kind() != RequestErrorKind::kNotFound) throw;
  }
}

}  // namespace

grpc::Status SimulationService::GetSweep(grpc::ServerContext* context,
                                         const v1::GetSweepRequest* request,
                                         v1::SweepProgress* response) {
  return Admit(*context, "GetSweep", [&]() -> grpc::Status {
    *response = SweepProgressOf(request->sweep_id(), KnownSweepRuns(*runs_, request->sweep_id()));
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::CancelSweep(grpc::ServerContext* context,
                                            const v1::CancelSweepRequest* request,
                                            v1::SweepProgress* response) {
  return Admit(*context, "CancelSweep", [&]() -> grpc::Status {
    const std::string& id = request->sweep_id();
    std::vector<v1::RunInfo> runs = KnownSweepRuns(*runs_, id);
    const bool admin = authorizer_->CallerHas(*context, Role::kAdmin);
    for (const v1::RunInfo& run : runs) {  // every run checked before any is cancelled
      if (!admin && !run.owner().empty() && run.owner() != authorizer_->CallerId(*context)) {
        return grpc::Status(grpc::StatusCode::PERMISSION_DENIED,
                            "sweep " + id + " has runs started with another token (" + run.id() +
                                "); only that token or an admin token may cancel it");
      }
    }
    const auto until = std::chrono::steady_clock::now() + kCancelWait;
    // The mark first: StartSweep refuses later slices from now on. Twice: a slice that passed
    // StartSweep's check before the mark, started while the first pass ran, is cancelled (and
    // marked) too.
    runs_->MarkSweepCancelled(id);
    for (int pass = 0; pass < 2; ++pass) {
      for (const v1::RunInfo& run : runs) {
        if (IsFinalState(run.state())) continue;
        v1::CancelRunRequest cancel;
        cancel.set_run_id(run.id());
        v1::RunInfo now;
        // CancelRun's own path: here, or forwarded to the replica integrating the run.
        if (grpc::Status status = CancelRun(context, &cancel, &now);
            !status.ok() && status.error_code() != grpc::StatusCode::NOT_FOUND) {
          return status;
        }
      }
      for (const v1::RunInfo& run : runs) AwaitEnded(*runs_, run, until);
      runs_->MarkSweepCancelled(id);
      runs = runs_->SweepRuns(id);
    }
    *response = SweepProgressOf(id, runs);
    response->set_cancelled(true);
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
