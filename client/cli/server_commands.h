// The commands that talk to a server: submit, models, runs, run, result, cancel, delete, keep,
// retention, health
// (README.md, "Server, viewer and CLI by hand"). Each callback stores its exit code in *exit_code.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>

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
void AddHealthCommand(CLI::App& app, std::shared_ptr<const ClientOptions> options,
                      int* exit_code);  // health (gRPC health checking)

}  // namespace mbstream::cli
