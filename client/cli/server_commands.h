// The commands that talk to a server: submit, models, runs, run, result, cancel, delete, keep,
// retention, storage, backup, health
// (README.md, "Server, viewer and CLI by hand"). Each callback stores its exit code in *exit_code.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "client/cli/server_connection.h"

namespace mbstream::cli {

void AddSubmitCommand(CLI::App& app, std::shared_ptr<const ClientOptions> options, int* exit_code);
void AddListCommands(CLI::App& app, std::shared_ptr<const ClientOptions> options,
                     int* exit_code);  // models, runs
void AddRunCommand(CLI::App& app, std::shared_ptr<const ClientOptions> options, int* exit_code);
void AddSweepCommand(CLI::App& app, std::shared_ptr<const ClientOptions> options,
                     int* exit_code);  // sweep (sweep_command.cc)
void AddResultCommands(CLI::App& app, std::shared_ptr<const ClientOptions> options,
                       int* exit_code);  // result, cancel
void AddReplayCommands(CLI::App& app, std::shared_ptr<const ClientOptions> options,
                       int* exit_code);  // probe-sets, replay
void AddDataCommands(CLI::App& app, std::shared_ptr<const ClientOptions> options,
                     int* exit_code);  // delete, keep, retention
void AddStorageCommands(CLI::App& app, std::shared_ptr<const ClientOptions> options,
                        int* exit_code);  // storage, backup (storage_commands.cc)
// `mbstream sweep --status ID` (GetSweep) and `--cancel ID` (CancelSweep; also `mbstream cancel
// --sweep ID`): the sweep's progress line printed, an RPC error reported as `command`'s
// (sweep_command.cc). Returns the exit code.
int SweepCall(const ClientOptions& client, const std::string& id, bool cancel,
              const std::string& command);

void AddHealthCommand(CLI::App& app, std::shared_ptr<const ClientOptions> options,
                      int* exit_code);  // health (gRPC health checking)

}  // namespace mbstream::cli
