// mbstream-server's command line: every flag, its default and its unit, bound to a
// ServerConfig (README.md, "Server, viewer and CLI by hand").
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "server/app/server_host.h"

namespace mbstream {

// The flags given in MiB and the log level: converted into `config` by ServerFlags::Apply.
struct ServerFlags {
  explicit ServerFlags(const ServerConfig& config);
  // Adds every flag to `app`, bound to `config` (which must outlive the parse) and to this.
  void AddTo(CLI::App& app, ServerConfig* config);
  // After the parse: the MiB flags into bytes, the message limit raised to hold a bundle.
  void Apply(ServerConfig* config) const;

  double max_model_mb, max_asset_mb, max_models_mb, max_message_mb, min_free_mb;
  std::string log_level = "info";
};

}  // namespace mbstream
