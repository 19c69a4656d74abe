// `mbstream probe-sets RUN` (the probe sets of a run's replays) and `mbstream replay RUN`
// (the server streams a stored run to its --follow viewers as if it were running now).
#include <cstdio>
#include <iostream>

#include "client/cli/server_commands.h"

namespace mbstream::cli {

namespace {

int ListProbeSets(const ClientOptions& client, const std::string& run_id) {
  grpc::ClientContext context;
  v1::ListProbeSetsRequest request;
  request.set_run_id(run_id);
  v1::ListProbeSetsResponse response;
  const grpc::Status status =
      ConnectSimulation(client)->ListProbeSets(&context, request, &response);
  if (!status.ok()) return ReportRpcError("probe-sets", client, status);
  std::printf("%-20s %8s %-24s %s\n", "ID", "REPORTS", "VIEWER", "SCENE");
  for (const v1::ProbeSet& set : response.sets()) {
    std::printf("%-20s %8lld %-24s %s\n", set.id().c_str(), static_cast<long long>(set.reports()),
                set.viewer().c_str(), set.scene().c_str());
  }
  return 0;
}

int Replay(const ClientOptions& client, const std::string& run_id, double speed) {
  grpc::ClientContext context;
  v1::ReplayRunRequest request;
  request.set_run_id(run_id);
  request.set_speed(speed);
  v1::RunInfo info;
  const grpc::Status status = ConnectSimulation(client)->ReplayRun(&context, request, &info);
  if (!status.ok()) return ReportRpcError("replay", client, status);
  std::cout << run_id << ": replaying " << info.frames() << " frames (" << info.t_s()
            << " s) to the server's --follow viewers\n";
  return 0;
}

}  // namespace

void AddReplayCommands(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  auto sets_run = std::make_shared<std::string>();
  CLI::App* sets = app.add_subcommand("probe-sets", "list the probe sets of a run's replays");
  sets->add_option("run", *sets_run, "run id")->required();
  sets->callback([client, sets_run, exit_code] { *exit_code = ListProbeSets(*client, *sets_run); });

  auto replay_run = std::make_shared<std::string>();
  auto speed = std::make_shared<double>(1.0);
  CLI::App* replay =
      app.add_subcommand("replay", "stream a stored run to the server's --follow viewers");
  replay->add_option("run", *replay_run, "run id")->required();
  replay->add_option("--speed", *speed, "simulated s per wall s (1 = real time)")
      ->check(CLI::Range(0.001, 1000.0));
  replay->callback([client, replay_run, speed, exit_code] {
    *exit_code = Replay(*client, *replay_run, *speed);
  });
}

}  // namespace mbstream::cli
