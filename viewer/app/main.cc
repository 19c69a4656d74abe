// mbstream-viewer: the VTK visualisation server's program.
//
// Without a server (this file's commands today):
//   mbstream-viewer --check FILE [--asset-dir DIR]...
//   mbstream-viewer --scene FILE [--pose Q1,Q2,...] [--offscreen] [--snapshot OUT.png]
//   mbstream-viewer --urdf FILE  [--pose Q1,Q2,...] [--offscreen] [--snapshot OUT.png]
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <iostream>

#include "viewer/app/commands.h"

int main(int argc, char** argv) {
  CLI::App app{
      "mbstream-viewer: shows a mechanism from a scene script or URDF and answers "
      "probes"};
  app.set_version_flag("--version", "mbstream-viewer 0.1.0");

  std::string check_file;
  std::vector<std::string> asset_dirs;
  mbstream::viewer::PoseOptions pose;
  std::string size = "960x720";
  auto* check = app.add_option("--check", check_file,
                               "Translate a scene script without rendering: print every error "
                               "as FILE:LINE:COL: message (exit 1) or a summary (exit 0)")
                    ->check(CLI::ExistingFile);
  app.add_option("--asset-dir", asset_dirs,
                 "Directory with the STL files of Part commands "
                 "(repeatable; the script's directory is searched last)")
      ->check(CLI::ExistingDirectory);
  auto* scene =
      app.add_option("--scene", pose.scene_file, "Scene script to show")->check(CLI::ExistingFile);
  auto* urdf = app.add_option("--urdf", pose.urdf_file,
                              "URDF whose visuals (box, cylinder, sphere, STL) make the scene")
                   ->check(CLI::ExistingFile);
  auto* pose_option = app.add_option("--pose", pose.pose,
                                     "Joint values Q1,Q2,... in degrees (revolute) or mm "
                                     "(prismatic), like the script's Initial");
  app.add_flag("--offscreen", pose.offscreen, "Render without a window (needs Xvfb: xvfb-run -a)");
  auto* snapshot = app.add_option("--snapshot", pose.snapshot, "Write the pose as a PNG and exit");
  app.add_option("--size", size, "Image size WIDTHxHEIGHT")->default_val("960x720");

  // ---- The simulation-server link goes here (not yet built): --server ADDR, --run ID,
  // --follow, --listen ADDR, --record FILE.ogv, --snapshots DIR. It will build a Scene the
  // same way (LoadScene, or the script and assets the server sends), call
  // Scene::SetJointValues + Scene::ProbeReports on its network thread for every frame, and
  // Scene::Render on this thread at display rate.

  check->excludes(scene)->excludes(urdf)->excludes(pose_option)->excludes(snapshot);
  scene->excludes(urdf);

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

  if (const size_t x = size.find('x'); x == std::string::npos ||
                                       (pose.width = std::atoi(size.c_str())) <= 0 ||
                                       (pose.height = std::atoi(size.c_str() + x + 1)) <= 0) {
    std::cerr << "mbstream-viewer: --size '" << size << "' is not WIDTHxHEIGHT, e.g. 640x480\n";
    return 2;
  }
  if (pose.pose && pose.scene_file.empty() && pose.urdf_file.empty()) {
    std::cerr << "mbstream-viewer: --pose needs --scene FILE or --urdf FILE\n";
    return 2;
  }
  if (!check_file.empty()) return mbstream::viewer::RunCheck(check_file, asset_dirs);
  if (!pose.scene_file.empty() || !pose.urdf_file.empty()) {
    pose.asset_dirs = asset_dirs;
    return mbstream::viewer::RunPose(pose);
  }
  std::cerr << "mbstream-viewer: nothing to do: give --check FILE, --scene FILE or --urdf FILE "
               "(the --server link is not built yet); see mbstream-viewer --help\n";
  return 2;
}
