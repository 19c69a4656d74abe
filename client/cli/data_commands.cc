// `mbstream delete RUN...`, `mbstream delete --model MODEL [--with-runs]` (the admin's
// deletions: DeleteRuns, DeleteModel), `mbstream keep RUN... [--off]` (SetKeep) and
// `mbstream retention --dry-run` (RetentionPlan).
#include <cstdio>
#include <iostream>
#include <vector>

#include "client/cli/server_commands.h"
#include "shared/common/check.h"

namespace mbstream::cli {

namespace {

struct DeleteOptions {
  std::vector<std::string> run_ids;
  std::string model;
  bool with_runs = false;
};

void PrintDeleted(const v1::RunInfo& run) {
  std::cout << "deleted run " << run.id() << " (" << v1::RunState_Name(run.state()) << ", "
            << run.frames() << " frames)\n";
}

int Delete(const ClientOptions& client, const DeleteOptions& options) {
  if (options.model.empty() == options.run_ids.empty()) {
    throw InputError(
        "delete takes run ids (mbstream delete RUN...) or a model (mbstream delete --model "
        "MODEL [--with-runs]), not both nor neither");
  }
  if (options.with_runs && options.model.empty()) {
    throw InputError("--with-runs goes with --model MODEL");
  }
  grpc::ClientContext context;
  if (options.model.empty()) {
    v1::DeleteRunsRequest request;
    for (const std::string& id : options.run_ids) request.add_run_ids(id);
    v1::DeleteRunsResponse response;
    const grpc::Status status = ConnectSimulation(client)->DeleteRuns(&context, request, &response);
    if (!status.ok()) return ReportRpcError("delete", client, status);
    for (const v1::RunInfo& run : response.runs()) PrintDeleted(run);
    return 0;
  }
  v1::DeleteModelRequest request;
  request.set_model(options.model);
  request.set_with_runs(options.with_runs);
  v1::DeleteModelResponse response;
  const grpc::Status status = ConnectSimulation(client)->DeleteModel(&context, request, &response);
  if (!status.ok()) return ReportRpcError("delete", client, status);
  for (const v1::RunInfo& run : response.runs()) PrintDeleted(run);
  std::cout << "deleted model " << response.model().id() << " '" << response.model().name()
            << "'\n";
  return 0;
}

int Keep(const ClientOptions& client, const std::vector<std::string>& run_ids, bool off) {
  std::unique_ptr<v1::Simulation::Stub> stub = ConnectSimulation(client);
  for (const std::string& id : run_ids) {
    grpc::ClientContext context;
    v1::SetKeepRequest request;
    request.set_run_id(id);
    request.set_keep(!off);
    v1::RunInfo info;
    const grpc::Status status = stub->SetKeep(&context, request, &info);
    if (!status.ok()) return ReportRpcError("keep", client, status);
    std::cout << info.id()
              << (info.keep() ? " kept: retention never deletes it\n"
                              : " no longer kept: retention may delete it\n");
  }
  return 0;
}

int Retention(const ClientOptions& client) {
  grpc::ClientContext context;
  v1::RetentionPlanResponse plan;
  const grpc::Status status =
      ConnectSimulation(client)->RetentionPlan(&context, v1::RetentionPlanRequest(), &plan);
  if (!status.ok()) return ReportRpcError("retention", client, status);
  if (plan.retain_runs() == 0 && plan.retain_days() == 0.0) {
    std::cout << "no retention: the server keeps every run (mbstream-server --retain-runs N, "
                 "--retain-days D)\n";
    return 0;
  }
  std::cout << "retention: the newest " << plan.retain_runs() << " ended runs (0 = any number), "
            << "ended within " << plan.retain_days() << " days (0 = any age), and runs marked "
            << "keep; would delete " << plan.runs_size() << " runs now (dry run: none deleted)\n";
  for (const v1::RunInfo& r : plan.runs()) {
    std::printf("%-24s %-20s %-12s %8lld frames\n", r.id().c_str(), r.model_name().c_str(),
                v1::RunState_Name(r.state()).c_str(), static_cast<long long>(r.frames()));
  }
  return 0;
}

}  // namespace

void AddDataCommands(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  auto options = std::make_shared<DeleteOptions>();
  CLI::App* remove = app.add_subcommand(
      "delete",
      "delete runs (each whole: frames, probe reports, probe sets; a running run is cancelled "
      "first) or a model; needs an admin token");
  remove->add_option("runs", options->run_ids, "run ids");
  remove->add_option("--model", options->model, "delete this model (id or name) instead");
  remove->add_flag("--with-runs", options->with_runs,
                   "with --model: delete its runs too (without: refused while it has runs)");
  remove->callback([client, options, exit_code] { *exit_code = Delete(*client, *options); });

  auto keep_ids = std::make_shared<std::vector<std::string>>();
  auto off = std::make_shared<bool>(false);
  CLI::App* keep =
      app.add_subcommand("keep", "mark ended runs to be kept: retention never deletes them");
  keep->add_option("runs", *keep_ids, "run ids")->required();
  keep->add_flag("--off", *off, "no longer kept: retention may delete them again");
  keep->callback(
      [client, keep_ids, off, exit_code] { *exit_code = Keep(*client, *keep_ids, *off); });

  CLI::App* retention = app.add_subcommand(
      "retention", "the server's retention and the runs it would delete now (a dry run)");
  auto dry_run = std::make_shared<bool>(true);
  retention->add_flag("--dry-run", *dry_run, "(the default and only mode: nothing is deleted)");
  retention->callback([client, dry_run, exit_code] { *exit_code = Retention(*client); });
}

}  // namespace mbstream::cli
