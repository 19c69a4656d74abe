// The role every RPC of mbstream.v1.Simulation needs: the one list the service's gate reads
// (SimulationService::Admit). A test checks that it names every method of the service.
#pragma once

#include <string_view>

#include "server/service/authorizer.h"

namespace mbstream {

struct RpcRole {
  std::string_view method;  // the method's name in simulation_service.proto
  Role role;
};

inline constexpr RpcRole kRpcRoles[] = {
    {"SubmitModel", Role::kSubmit},  // compiles and stores a model
    {"ListModels", Role::kView},     //
    {"GetModel", Role::kView},       //
    {"StartRun", Role::kRun},        // occupies a worker
    {"StartRuns", Role::kRun},       // occupies workers
    {"StartSweep", Role::kRun},      // occupies workers
    {"CancelRun", Role::kRun},       // the run's own token, or admin (checked in the handler)
    {"GetRun", Role::kView},         //
    {"ListRuns", Role::kView},       //
    {"GetResult", Role::kView},      //
    {"GetResults", Role::kView},     //
    {"WatchRun", Role::kView},       //
    {"Subscribe", Role::kView},      // viewers; their probe reports are checked per stream
    {"Control", Role::kRun},         // starts (or attaches to) a run and commands it
    {"ListProbeSets", Role::kView},  //
    {"ReplayRun", Role::kRun},       // streams a stored run to every follower
    {"DeleteRuns", Role::kAdmin},    // data of every user
    {"DeleteModel", Role::kAdmin},   //
    {"SetKeep", Role::kRun},         // protects a run from retention (or no longer)
    {"RetentionPlan", Role::kView},  // a dry run: deletes nothing
    {"ExportMcap", Role::kView},     // a stored run as MCAP
    {"GetSweep", Role::kView},       //
    {"CancelSweep", Role::kRun},     // the runs' own token, or admin (checked in the handler)
    // Where the data is and what it takes; a copy of every user's data.
    {"GetStorage", Role::kAdmin},
    {"BackupStorage", Role::kAdmin},
};

// The role of `method`; a method missing from kRpcRoles is a bug (InternalError).
Role RoleOf(std::string_view method);

}  // namespace mbstream
