// mbstream-viewer: the VTK visualisation server's program.
//
// With a simulation server:
//   mbstream-viewer --server ADDR (--run ID | --follow) [--scene FILE] [--offscreen]
//                   [--speed X] [--loop] [--from-frame N] [--paused] [--compare RUN]
//                   [--record FILE.ogv] [--snapshots DIR] [--listen ADDR] [--ca F]
//                   [--token-file F] [--exit-after-runs N]
//                   [--web HOST:PORT [--web-tls CERT,KEY] [--web-max-pages N]]
// Without a server:
//   mbstream-viewer --check FILE [--asset-dir DIR]...
//   mbstream-viewer --scene FILE [--pose Q1,Q2,...] [--offscreen] [--snapshot OUT.png]
//   mbstream-viewer --model FILE [--package-path DIR]... [--pose Q1,Q2,...] [--offscreen]
//                   [--snapshot OUT.png]      (FILE a URDF or an SDFormat file; --urdf: alias)
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <iostream>

#include "viewer/app/commands.h"
#include "viewer/app/viewer_flags.h"

int main(int argc, char** argv) {
  CLI::App app{
      "mbstream-viewer: shows a mechanism from a scene script, a URDF or an SDFormat file and "
      "answers probes"};
  app.set_version_flag("--version", "mbstream-viewer 0.1.0");
  mbstream::viewer::ViewerFlags flags;
  mbstream::viewer::AddViewerFlags(app, flags);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "mbstream-viewer: " << e.what() << "; see mbstream-viewer --help\n";
    return 2;
  }
  if (const std::string error = mbstream::viewer::FinishViewerFlags(flags); !error.empty()) {
    std::cerr << "mbstream-viewer: " << error << "\n";
    return 2;
  }
  mbstream::viewer::PoseOptions& pose = flags.pose;
  mbstream::viewer::LinkCommandOptions& link = flags.link;
  if (!flags.check_file.empty()) {
    return mbstream::viewer::RunCheck(flags.check_file, flags.asset_dirs);
  }
  if (!link.link.server.empty()) {
    if (link.link.run_id.empty() && !link.link.follow) {
      std::cerr << "mbstream-viewer: --server needs --run ID or --follow\n";
      return 2;
    }
    link.scene_file = pose.scene_file;
    link.model_file = pose.model_file;
    link.package_paths = pose.package_paths;
    link.floating_base = pose.floating_base;
    link.asset_dirs = flags.asset_dirs;
    link.offscreen = pose.offscreen;
    link.width = pose.width;
    link.height = pose.height;
    link.triangle_budget = pose.triangle_budget;
    return mbstream::viewer::RunLink(link);
  }
  if (!pose.scene_file.empty() || !pose.model_file.empty()) {
    pose.asset_dirs = flags.asset_dirs;
    return mbstream::viewer::RunPose(pose);
  }
  std::cerr << "mbstream-viewer: nothing to do: give --check FILE, --scene FILE or --model FILE "
               "or --server ADDR --follow; see mbstream-viewer --help\n";
  return 2;
}
