// mbstream: the command-line client. `mbstream --help` lists the commands.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

#include <memory>

#include "client/cli/exit_codes.h"
#include "client/cli/server_commands.h"
#include "client/cli/simulate_command.h"
#include "shared/common/check.h"

int main(int argc, char** argv) {
  CLI::App app{"mbstream: simulate articulated mechanisms and watch them move", "mbstream"};
  app.require_subcommand(1);
  int exit_code = 0;
  auto client = std::make_shared<mbstream::cli::ClientOptions>();
  mbstream::cli::AddClientOptions(app, client.get());
  mbstream::cli::AddSimulateCommand(app, &exit_code);
  mbstream::cli::AddSubmitCommand(app, client, &exit_code);
  mbstream::cli::AddListCommands(app, client, &exit_code);
  mbstream::cli::AddRunCommand(app, client, &exit_code);
  mbstream::cli::AddSweepCommand(app, client, &exit_code);
  mbstream::cli::AddResultCommands(app, client, &exit_code);
  mbstream::cli::AddReplayCommands(app, client, &exit_code);
  mbstream::cli::AddDataCommands(app, client, &exit_code);
  mbstream::cli::AddStorageCommands(app, client, &exit_code);
  mbstream::cli::AddHealthCommand(app, client, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // CLI11 prints the help (exit 0) or the usage error; a usage error is a bad request,
    // exit 2 as the README's exit codes say, not CLI11's own codes (105, 106, ...).
    return app.exit(error) == 0 ? mbstream::cli::kExitOk : mbstream::cli::kExitBadRequest;
  } catch (const mbstream::InputError& error) {
    std::cerr << "mbstream: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "mbstream: internal error: " << error.what() << "\n";
    return 3;
  }
  return exit_code;
}
