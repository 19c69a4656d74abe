// mbstream: the command-line client. `mbstream --help` lists the commands.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

#include "client/cli/simulate_command.h"

int main(int argc, char** argv) {
  CLI::App app{"mbstream: simulate articulated mechanisms and watch them move", "mbstream"};
  app.require_subcommand(1);
  int exit_code = 0;
  mbstream::cli::AddSimulateCommand(app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const std::exception& error) {
    std::cerr << "mbstream: internal error: " << error.what() << "\n";
    return 3;
  }
  return exit_code;
}
