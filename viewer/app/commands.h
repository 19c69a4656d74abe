// The mbstream-viewer commands that need no simulation server.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "shared/net/server_credentials.h"
#include "viewer/link/render_loop.h"
#include "viewer/link/subscriber_link.h"
#include "viewer/web/web_server.h"

namespace mbstream::viewer {

// --check FILE [--asset-dir DIR]...: every error as FILE:LINE:COL: message on stderr
// (returns 1), or the summary on stdout (returns 0).
int RunCheck(const std::string& file, const std::vector<std::string>& asset_dirs);

struct PoseOptions {
  std::string scene_file;  // a scene script, or empty
  std::string model_file;  // a URDF or SDFormat file (--model, alias --urdf), or empty
  std::vector<std::string> package_paths;  // --package-path: where package:// meshes are
  bool floating_base = false;              // --floating-base: a URDF's root moves freely
  std::vector<std::string> asset_dirs;
  std::optional<std::string> pose;  // "Q1,Q2,...", degrees or mm
  bool offscreen = false;
  std::optional<std::string> snapshot;  // PNG path
  int width = 960;
  int height = 720;
  long long triangle_budget = SceneOptions::kDefaultTriangleBudget;  // --triangle-budget
};

// --scene FILE | --model FILE [--pose ...] [--offscreen] [--snapshot OUT.png]: poses the
// scene, prints the probes, then snapshots, or shows the window until it is closed.
// Returns 0, 1 (bad input) or 2 (no display).
int RunPose(const PoseOptions& options);

struct LinkCommandOptions {
  LinkOptions link;        // --server, --run | --follow, security, --exit-after-runs
  RenderOptions render;    // --fps, --record, --snapshots, --snapshot-every
  std::string scene_file;  // --scene: instead of the model's own scene
  // --model: the model file on disk (its meshes found as submit finds them, with their
  // .mtl files and textures, which a bundle does not carry) instead of the run's bundle.
  std::string model_file;
  std::vector<std::string> package_paths;
  bool floating_base = false;
  std::vector<std::string> asset_dirs;
  std::string listen;         // the Viewer control service; empty = none
  WebOptions web;             // --web HOST:PORT (address empty = none), --web-root, --web-max-pages
  net::ServerTls listen_tls;  // its TLS (--listen-tls-cert/--listen-tls-key)
  bool offscreen = false;
  int width = 960;
  int height = 720;
  long long triangle_budget = SceneOptions::kDefaultTriangleBudget;  // --triangle-budget
};

// --server ADDR (--run ID | --follow) ...: shows runs live and answers their probes.
// Returns 0, 1 (a fatal error, logged) or 2 (no display).
int RunLink(const LinkCommandOptions& options);

}  // namespace mbstream::viewer
