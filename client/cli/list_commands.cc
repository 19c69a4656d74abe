// `mbstream models` and `mbstream runs [--model M] [--limit N]`: one line per item.
#include <cstdio>
#include <iostream>

#include "client/cli/server_commands.h"

namespace mbstream::cli {

namespace {

int ListModels(const ClientOptions& client) {
  grpc::ClientContext context;
  v1::ListModelsResponse response;
  const grpc::Status status =
      ConnectSimulation(client)->ListModels(&context, v1::ListModelsRequest(), &response);
  if (!status.ok()) return ReportRpcError("models", client, status);
  std::printf("%-28s %-20s %5s %6s %6s %s\n", "ID", "NAME", "DOFS", "LINKS", "SCENE", "ORIGIN");
  for (const v1::ModelInfo& m : response.models()) {
    std::printf("%-28s %-20s %5d %6d %6s %s\n", m.id().c_str(), m.name().c_str(), m.dofs(),
                m.links(), m.has_scene() ? "yes" : "no", m.builtin() ? "built-in" : "submitted");
  }
  return 0;
}

// Pages through ListRuns (newest first) until `limit` runs (0 = all) are printed. The ID
// column holds a run id (r-YYYYMMDD-HHMMSS-8 hex digits: 26 characters).
int ListRuns(const ClientOptions& client, const std::string& model, int limit) {
  std::unique_ptr<v1::Simulation::Stub> stub = ConnectSimulation(client);
  v1::ListRunsRequest request;
  request.set_model(model);
  request.set_limit(limit);
  std::printf("%-26s %-20s %-20s %9s %8s %s\n", "ID", "MODEL", "STATE", "T (s)", "FRAMES",
              "MESSAGE");
  do {
    grpc::ClientContext context;
    v1::ListRunsResponse response;
    const grpc::Status status = stub->ListRuns(&context, request, &response);
    if (!status.ok()) return ReportRpcError("runs", client, status);
    for (const v1::RunInfo& r : response.runs()) {
      std::printf("%-26s %-20s %-20s %9.3f %8lld %s\n", r.id().c_str(), r.model_name().c_str(),
                  v1::RunState_Name(r.state()).c_str(), r.t_s(), static_cast<long long>(r.frames()),
                  (r.controller().empty() ? r.message()
                                          : "[controlled by " + r.controller() + "] " + r.message())
                      .c_str());
    }
    request.set_page_token(response.next_page_token());
  } while (!request.page_token().empty());
  return 0;
}

}  // namespace

void AddListCommands(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  CLI::App* models = app.add_subcommand("models", "list the server's models");
  models->callback([client, exit_code] { *exit_code = ListModels(*client); });

  auto model = std::make_shared<std::string>();
  auto limit = std::make_shared<int>(0);
  CLI::App* runs = app.add_subcommand("runs", "list the server's runs, newest first");
  runs->add_option("--model", *model, "only this model's runs (id or name)");
  runs->add_option("--limit", *limit, "at most this many (0 = all)")->check(CLI::NonNegativeNumber);
  runs->callback(
      [client, model, limit, exit_code] { *exit_code = ListRuns(*client, *model, *limit); });
}

}  // namespace mbstream::cli
