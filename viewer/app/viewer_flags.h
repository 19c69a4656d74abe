// mbstream-viewer's command line: every flag, what it fills and how flags go together
// (CLI11), and the checks that follow parsing. main.cc dispatches on the result.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "viewer/app/commands.h"

namespace mbstream::viewer {

struct ViewerFlags {
  std::string check_file;               // --check
  std::vector<std::string> asset_dirs;  // --asset-dir
  PoseOptions pose;                     // without a server: --scene/--model, --pose...
  std::string size = "960x720";         // --size WIDTHxHEIGHT
  LinkCommandOptions link;              // with a server: --server, --run/--follow, --web...
  std::vector<std::string> web_tls;     // --web-tls CERT,KEY
};

// Declares every flag on `app`; parsing fills `flags`.
void AddViewerFlags(CLI::App& app, ViewerFlags& flags);

// After parsing: --size into the pose's width and height, --web-tls into the web options,
// and the checks CLI11 cannot express. Returns the message of a usage error, or "".
std::string FinishViewerFlags(ViewerFlags& flags);

}  // namespace mbstream::viewer
