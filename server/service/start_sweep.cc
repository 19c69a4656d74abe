// StartSweep: a parameter sweep expanded here (server/spec/spec_override.h) and queued as
// StartRuns queues runs, a slice at a time.
#include <algorithm>

#include "common/check.h"
#include "server/runs/request_error.h"
#include "server/runs/timed_id.h"
#include "server/service/simulation_service.h"
#include "server/spec/spec_override.h"

namespace mbstream {

namespace {

// Most points of one sweep: its expansion is redone for every slice.
constexpr long kMaxSweepPoints = 100'000;

SweepPoints PointsOf(const v1::StartSweepRequest& request) {
  if (request.grid_size() > 0 && (request.list_size() > 0 || request.list_paths_size() > 0)) {
    throw InputError("StartSweep: give a grid or a list, not both");
  }
  if (request.grid_size() > 0) {
    std::vector<std::string> paths;
    std::vector<std::vector<std::string>> values;
    for (const v1::SweepAxis& axis : request.grid()) {
      paths.push_back(axis.path());
      values.emplace_back(axis.values().begin(), axis.values().end());
    }
    return GridPoints(paths, values, kMaxSweepPoints, "grid");
  }
  if (request.list_size() == 0) {
    throw InputError("StartSweep: the sweep has no points; give grid axes or list points");
  }
  if (request.list_size() > kMaxSweepPoints) {
    throw InputError("list: more than " + std::to_string(kMaxSweepPoints) +
                     " points; split the sweep");
  }
  SweepPoints sweep;
  sweep.paths.assign(request.list_paths().begin(), request.list_paths().end());
  for (const v1::SweepPoint& point : request.list()) {
    sweep.points.emplace_back(point.values().begin(), point.values().end());
  }
  return sweep;
}

}  // namespace

grpc::Status SimulationService::StartSweep(grpc::ServerContext* context,
                                           const v1::StartSweepRequest* request,
                                           v1::StartSweepResponse* response) {
  return Admit(*context, "StartSweep", [&]() -> grpc::Status {
    const SweepPoints sweep = PointsOf(*request);
    const long total = static_cast<long>(sweep.points.size());
    if (request->first_point() < 0 || request->first_point() > total) {
      throw InputError("first_point is " + std::to_string(request->first_point()) +
                       "; the sweep has " + std::to_string(total) + " points (0.." +
                       std::to_string(total) + ")");
    }
    if (request->max_runs() < 0) {
      throw InputError("max_runs is " + std::to_string(request->max_runs()) +
                       "; give 0 (all that are left) or the most runs to start now");
    }
    const long first = request->first_point();
    const long count = request->max_runs() == 0
                           ? total - first
                           : std::min<long>(request->max_runs(), total - first);
    // The first slice expands every point, so that a value of the wrong type or path fails
    // the sweep before any run starts; later slices only their own.
    if (first == 0) ExpandSweep(request->base(), sweep, "sweep");
    google::protobuf::RepeatedPtrField<v1::RunSpec> slice;
    for (v1::RunSpec& spec : ExpandSweep(request->base(), sweep, "sweep", first, count)) {
      *slice.Add() = std::move(spec);
    }
    const std::string& given = request->sweep_id();
    if (!given.empty() &&
        (given.size() > 64 || given.rfind("s-", 0) != 0 ||
         given.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-") != std::string::npos)) {
      throw InputError("sweep_id: give the id the sweep's first StartSweep returned (s-...)");
    }
    if (!given.empty() && runs_->SweepCancelled(given)) {
      throw RequestError(RequestErrorKind::kFailedPrecondition,
                         "sweep " + given + " was cancelled (CancelSweep); start a new sweep");
    }
    const std::string id = given.empty() ? NewTimedId("s-") : given;
    response->set_sweep_id(id);
    for (const std::string& path : sweep.paths) response->add_paths(path);
    if (count > 0) {
      for (v1::RunInfo& info :
           runs_->StartMany(request->model(), slice, authorizer_->CallerId(*context), id,
                            static_cast<int>(first), static_cast<int>(total))) {
        *response->add_runs() = std::move(info);
      }
    }
    for (long k = first; k < first + count; ++k) {
      v1::SweepPoint& point = *response->add_points();
      for (const std::string& value : sweep.points[static_cast<size_t>(k)]) point.add_values(value);
    }
    response->set_total_points(static_cast<int32_t>(total));
    response->set_next_point(static_cast<int32_t>(first + count));
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
