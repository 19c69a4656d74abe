// A Subscribe stream that replays a stored run (replay.proto): the plan (checked before the
// stream is accepted, so a bad request ends with its status code) and the paced sending.
#pragma once

#include <atomic>
#include <memory>
#include <optional>

#include <grpcpp/grpcpp.h>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/runs/model_registry.h"
#include "server/runs/replay_cursor.h"
#include "server/runs/replay_grid.h"
#include "server/runs/run_manager.h"
#include "server/service/replay_inbox.h"
#include "server/service/sent_frames.h"
#include "server/service/subscribe_call.h"

namespace mbstream {

struct ReplayPlan {
  v1::RunInfo run;
  std::optional<v1::RunInfo> ghost;  // compare_run_id's info
  std::unique_ptr<ReplayCursor> run_frames;
  std::unique_ptr<ReplayCursor> ghost_frames;
  ReplayGrid grid;
  v1::Replay options;
  int64_t start_step = 0;  // grid step of options.from_seq
};

// Checks `start` (run_id with `replay`) and opens the run's (and the ghost's) stored frames.
// Returns nullopt when the run is still queued or running and asks nothing a live run cannot
// give: it is then served live. Throws InputError (bad speed, seek out of range, runs that
// cannot be compared), RequestError (kNotFound; kFailedPrecondition for a seek, pause or
// comparison of a run that has not ended).
std::optional<ReplayPlan> PlanReplay(RunManager& runs, const v1::SubscribeRequest::Start& start);

// Checks a ReplayRequest's speed (Replay.speed and ReplayControl.speed): "" or why not.
std::string CheckReplaySpeed(double speed);

// The sender of a replay's Subscribe stream (subscribe_call.h): run_started, replay_state,
// the frames paced by their simulated times (and the viewer's controls as they come: its
// call's ReplayInbox), then run_ended (unless looping).
// `contacts`: the frames keep their stored contacts (SubscribeRequest.Start.contacts).
std::unique_ptr<SubscribeSender> NewReplaySender(ReplayPlan plan, int max_batch, bool contacts);

}  // namespace mbstream
