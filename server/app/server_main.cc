// mbstream-server: hosts models, integrates runs and streams them (flags: README.md,
// "Server, viewer and CLI by hand"; threads: docs/architecture.md).
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

#include "server/app/server_flags.h"
#include "server/app/server_host.h"
#include "server/app/server_signals.h"
#include "server/runs/release_memory.h"
#include "shared/common/check.h"
#include "shared/net/tls_files.h"

#ifndef MBSTREAM_DEFAULT_MODELS_DIR
#define MBSTREAM_DEFAULT_MODELS_DIR ""
#endif

int main(int argc, char** argv) {
  mbstream::UseMappingsForLargeBlocks();
  mbstream::ServerConfig config;
  config.models_dir =
      std::filesystem::exists(MBSTREAM_DEFAULT_MODELS_DIR) ? MBSTREAM_DEFAULT_MODELS_DIR : "";
  mbstream::ServerFlags flags(config);
  CLI::App app{"mbstream-server: simulate articulated mechanisms and stream their motion",
               "mbstream-server"};
  flags.AddTo(app, &config);
  CLI11_PARSE(app, argc, argv);
  flags.Apply(&config);
  spdlog::set_level(spdlog::level::from_str(flags.log_level));

  const sigset_t signals = mbstream::BlockStopSignals();
  mbstream::StopWatchdog watchdog;  // outlives the host: it bounds the host's shutdown
  std::unique_ptr<mbstream::ServerHost> host;
  try {
    host = mbstream::ServerHost::Start(config);
  } catch (const mbstream::InputError& error) {
    std::cerr << "mbstream-server: " << error.what() << "\n";
    return 2;
  }
  std::cout << "listening on " << host->address() << std::endl;
  if (!config.metrics.empty()) {
    std::cout << "metrics on http://" << host->metrics_address() << "/metrics" << std::endl;
  }
  spdlog::info("listening on {} (data in {})", host->address(),
               config.store.empty() ? config.data_dir : config.store);
  for (const std::string& warning : mbstream::ExposureWarnings(config)) spdlog::warn("{}", warning);
  mbstream::ServeUntilSignalled(*host, signals, watchdog);
  host.reset();
  spdlog::info("stopped");
  return 0;
}
