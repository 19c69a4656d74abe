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

int main(int argc, char** argv) {
  CLI::App app{
      "mbstream-viewer: shows a mechanism from a scene script, a URDF or an SDFormat file and "
      "answers probes"};
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
  auto* urdf =
      app.add_option("--model,--urdf", pose.model_file,
                     "URDF or SDFormat file (told apart by content) whose visuals (box, "
                     "cylinder, sphere, mesh files: Collada, OBJ, STL, glTF/GLB, PLY) "
                     "make the scene; meshes are found as mbstream submit finds them (with "
                     "--server: drawn for every run instead of the run's bundle, e.g. "
                     "for textures a bundle does not carry)")
          ->check(CLI::ExistingFile);
  app.add_option("--package-path", pose.package_paths,
                 "With --model: a folder searched for the ROS packages of package:// and "
                 "model:// meshes (repeatable; then $MBSTREAM_PACKAGE_PATH, then the model "
                 "file's ancestors)")
      ->check(CLI::ExistingDirectory)
      ->needs(urdf);
  auto* pose_option = app.add_option("--pose", pose.pose,
                                     "Joint values Q1,Q2,... in degrees (revolute) or mm "
                                     "(prismatic), like the script's Initial");
  app.add_flag("--offscreen", pose.offscreen, "Render without a window (needs Xvfb: xvfb-run -a)");
  auto* snapshot = app.add_option("--snapshot", pose.snapshot, "Write the pose as a PNG and exit");
  app.add_option("--size", size, "Image size WIDTHxHEIGHT")->default_val("960x720");
  app.add_option("--triangle-budget", pose.triangle_budget,
                 "Decimate a model whose meshes hold more triangles to about this many on "
                 "load, keeping the silhouette (0 = never)")
      ->default_val(mbstream::viewer::SceneOptions::kDefaultTriangleBudget)
      ->check(CLI::NonNegativeNumber);

  // ---- The simulation-server link.
  mbstream::viewer::LinkCommandOptions link;
  auto* server = app.add_option("--server", link.link.server,
                                "Simulation server to subscribe to: host:port or unix:/path");
  auto* run = app.add_option("--run", link.link.run_id, "Show this run (then exit)");
  auto* follow = app.add_flag("--follow", link.link.follow, "Show every run as it starts");
  auto* speed = app.add_option("--speed", link.link.replay.speed,
                               "Replay of an ended --run: simulated s per wall s (1 = real "
                               "time, 0 = as fast as the viewer takes frames)")
                    ->check(CLI::Range(0.0, 1000.0));
  auto* loop = app.add_flag("--loop", link.link.replay.loop,
                            "Replay: start again at the first frame after the last");
  auto* from_seq =
      app.add_option("--from-frame", link.link.replay.from_seq, "Replay: start at this frame (seq)")
          ->check(CLI::NonNegativeNumber);
  auto* paused = app.add_flag("--paused", link.link.replay.paused,
                              "Replay: start paused (space resumes, Left/Right step)");
  auto* compare = app.add_option("--compare", link.link.replay.compare_run_id,
                                 "Replay: show this ended run of the same model as a "
                                 "translucent ghost, with the distance between the TCPs");
  app.add_option("--exit-after-runs", link.link.exit_after_runs,
                 "With --follow: exit after this many runs ended (0 = never)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--ca", link.link.security.ca_file, "PEM CA of the server's certificate (TLS)")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-cert", link.link.security.cert_file, "Client certificate (PEM)")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-key", link.link.security.key_file, "Client certificate's key (PEM)")
      ->check(CLI::ExistingFile);
  app.add_option("--token-file", link.link.security.token_file,
                 "File whose first word is the access token (role view)")
      ->check(CLI::ExistingFile);
  app.add_option("--record", link.render.record_file, "Record the view as Ogg Theora (.ogv)");
  app.add_option("--snapshots", link.render.snapshots_dir, "Write PNG snapshots into DIR");
  app.add_option("--snapshot-every", link.render.snapshot_every, "Draws between snapshots")
      ->check(CLI::PositiveNumber);
  app.add_option("--fps", link.render.fps, "Draws per second (and the video's frame rate)")
      ->check(CLI::Range(1.0, 240.0));
  app.add_flag(
      "--no-hud", [&](int64_t) { link.render.hud = false; }, "Hide the status text");
  app.add_option("--listen", link.listen,
                 "Serve the Viewer control service (status, snapshot, load scene) on ADDR");
  app.add_option("--listen-tls-cert", link.listen_tls.cert_file, "TLS certificate of --listen")
      ->check(CLI::ExistingFile);
  app.add_option("--listen-tls-key", link.listen_tls.key_file, "TLS key of --listen")
      ->check(CLI::ExistingFile);
  auto* web = app.add_option("--web", link.web.address,
                             "Serve the scene to web browsers on HOST:PORT (port 0 = any free "
                             "port; prints 'web on http://HOST:PORT/'), e.g. 127.0.0.1:8080");
  link.web.root = MBSTREAM_WEB_ROOT;
  app.add_option("--web-root", link.web.root,
                 "The web page's folder (index.html, page.js, node_modules/three)")
      ->check(CLI::ExistingDirectory)
      ->needs(web);
  app.add_option("--web-max-pages", link.web.max_pages,
                 "Web pages open at once; more are refused (HTTP 503)")
      ->default_val(32)
      ->check(CLI::Range(1, 10000))
      ->needs(web);
  std::vector<std::string> web_tls;
  app.add_option("--web-tls", web_tls,
                 "Serve the pages over HTTPS/WSS with this PEM certificate and key: CERT,KEY")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::ExistingFile)
      ->needs(web);
  web->needs(server);
  run->needs(server)->excludes(follow);
  for (CLI::Option* replay_option : {speed, loop, from_seq, paused, compare}) {
    replay_option->needs(run);
  }
  follow->needs(server);

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
  if (pose.pose && pose.scene_file.empty() && pose.model_file.empty()) {
    std::cerr << "mbstream-viewer: --pose needs --scene FILE or --model FILE\n";
    return 2;
  }
  if (web_tls.size() == 2) {
    link.web.tls_cert_file = web_tls[0];
    link.web.tls_key_file = web_tls[1];
  }
  if (!check_file.empty()) return mbstream::viewer::RunCheck(check_file, asset_dirs);
  if (!link.link.server.empty()) {
    if (link.link.run_id.empty() && !link.link.follow) {
      std::cerr << "mbstream-viewer: --server needs --run ID or --follow\n";
      return 2;
    }
    link.scene_file = pose.scene_file;
    link.model_file = pose.model_file;
    link.package_paths = pose.package_paths;
    link.asset_dirs = asset_dirs;
    link.offscreen = pose.offscreen;
    link.width = pose.width;
    link.height = pose.height;
    link.triangle_budget = pose.triangle_budget;
    return mbstream::viewer::RunLink(link);
  }
  if (!pose.scene_file.empty() || !pose.model_file.empty()) {
    pose.asset_dirs = asset_dirs;
    return mbstream::viewer::RunPose(pose);
  }
  std::cerr << "mbstream-viewer: nothing to do: give --check FILE, --scene FILE or --model FILE "
               "or --server ADDR --follow; see mbstream-viewer --help\n";
  return 2;
}
