#include "viewer/app/viewer_flags.h"

#include <cstdlib>

namespace mbstream::viewer {
namespace {

// The options that are related to others (needs, excludes).
struct Related {
  CLI::Option* check = nullptr;
  CLI::Option* scene = nullptr;
  CLI::Option* model = nullptr;
  CLI::Option* pose = nullptr;
  CLI::Option* snapshot = nullptr;
  CLI::Option* server = nullptr;
  CLI::Option* run = nullptr;
  CLI::Option* follow = nullptr;
  CLI::Option* speed = nullptr;
  CLI::Option* loop = nullptr;
  CLI::Option* from_seq = nullptr;
  CLI::Option* paused = nullptr;
  CLI::Option* compare = nullptr;
  CLI::Option* web = nullptr;
};

// Without a server: --check, --scene, --model, --pose, --snapshot, --size...
void AddLocalFlags(CLI::App& app, ViewerFlags& flags, Related& o) {
  o.check = app.add_option("--check", flags.check_file,
                           "Translate a scene script without rendering: print every error "
                           "as FILE:LINE:COL: message (exit 1) or a summary (exit 0)")
                ->check(CLI::ExistingFile);
  app.add_option("--asset-dir", flags.asset_dirs,
                 "Directory with the STL files of Part commands "
                 "(repeatable; the script's directory is searched last)")
      ->check(CLI::ExistingDirectory);
  o.scene = app.add_option("--scene", flags.pose.scene_file, "Scene script to show")
                ->check(CLI::ExistingFile);
  o.model = app.add_option("--model,--urdf", flags.pose.model_file,
                           "URDF or SDFormat file (told apart by content) whose visuals (box, "
                           "cylinder, sphere, mesh files: Collada, OBJ, STL, glTF/GLB, PLY) "
                           "make the scene; meshes are found as mbstream submit finds them (with "
                           "--server: drawn for every run instead of the run's bundle, e.g. "
                           "for textures a bundle does not carry)")
                ->check(CLI::ExistingFile);
  app.add_option("--package-path", flags.pose.package_paths,
                 "With --model: a folder searched for the ROS packages of package:// and "
                 "model:// meshes (repeatable; then $MBSTREAM_PACKAGE_PATH, then the model "
                 "file's ancestors)")
      ->check(CLI::ExistingDirectory)
      ->needs(o.model);
  app.add_flag("--floating-base", flags.pose.floating_base,
               "With --model: a URDF's root link moves freely (a free joint named after it), "
               "as mbstream submit --floating-base")
      ->needs(o.model);
  o.pose = app.add_option("--pose", flags.pose.pose,
                          "Joint values Q1,Q2,... in degrees (revolute) or mm "
                          "(prismatic), like the script's Initial");
  app.add_flag("--offscreen", flags.pose.offscreen,
               "Render without a window (needs Xvfb: xvfb-run -a)");
  o.snapshot =
      app.add_option("--snapshot", flags.pose.snapshot, "Write the pose as a PNG and exit");
  app.add_option("--size", flags.size, "Image size WIDTHxHEIGHT")->default_val("960x720");
  app.add_option("--triangle-budget", flags.pose.triangle_budget,
                 "Decimate a model whose meshes hold more triangles to about this many on "
                 "load, keeping the silhouette (0 = never)")
      ->default_val(mbstream::viewer::SceneOptions::kDefaultTriangleBudget)
      ->check(CLI::NonNegativeNumber);
}

// The simulation-server link: --server, --run or --follow, replays, security.
void AddLinkFlags(CLI::App& app, ViewerFlags& flags, Related& o) {
  o.server = app.add_option("--server", flags.link.link.server,
                            "Simulation server to subscribe to: host:port or unix:/path");
  o.run = app.add_option("--run", flags.link.link.run_id, "Show this run (then exit)");
  o.follow = app.add_flag("--follow", flags.link.link.follow, "Show every run as it starts");
  o.speed = app.add_option("--speed", flags.link.link.replay.speed,
                           "Replay of an ended --run: simulated s per wall s (1 = real "
                           "time, 0 = as fast as the viewer takes frames)")
                ->check(CLI::Range(0.0, 1000.0));
  o.loop = app.add_flag("--loop", flags.link.link.replay.loop,
                        "Replay: start again at the first frame after the last");
  o.from_seq = app.add_option("--from-frame", flags.link.link.replay.from_seq,
                              "Replay: start at this frame (seq)")
                   ->check(CLI::NonNegativeNumber);
  o.paused = app.add_flag("--paused", flags.link.link.replay.paused,
                          "Replay: start paused (space resumes, Left/Right step)");
  o.compare = app.add_option("--compare", flags.link.link.replay.compare_run_id,
                             "Replay: show this ended run of the same model as a "
                             "translucent ghost, with the distance between the TCPs");
  app.add_flag("--contacts", flags.link.link.contacts,
               "Ask for each frame's contacts and draw them: a point and a force arrow each");
  app.add_option("--contact-scale", flags.link.link.contact_scale,
                 "With --contacts: force arrows' length in m per N (0 = the largest force so "
                 "far is 0.25 m)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--exit-after-runs", flags.link.link.exit_after_runs,
                 "With --follow: exit after this many runs ended (0 = never)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--ca", flags.link.link.security.ca_file,
                 "PEM CA of the server's certificate (TLS)")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-cert", flags.link.link.security.cert_file, "Client certificate (PEM)")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-key", flags.link.link.security.key_file, "Client certificate's key (PEM)")
      ->check(CLI::ExistingFile);
  app.add_option("--token-file", flags.link.link.security.token_file,
                 "File whose first word is the access token (role view)")
      ->check(CLI::ExistingFile);
}

// What the link draws and serves: recording, snapshots, the control service, the web view.
void AddOutputFlags(CLI::App& app, ViewerFlags& flags, Related& o) {
  app.add_option("--record", flags.link.render.record_file, "Record the view as Ogg Theora (.ogv)");
  app.add_option("--snapshots", flags.link.render.snapshots_dir, "Write PNG snapshots into DIR");
  app.add_option("--snapshot-every", flags.link.render.snapshot_every, "Draws between snapshots")
      ->check(CLI::PositiveNumber);
  app.add_option("--fps", flags.link.render.fps, "Draws per second (and the video's frame rate)")
      ->check(CLI::Range(1.0, 240.0));
  app.add_flag(
      "--no-hud", [&](int64_t) { flags.link.render.hud = false; }, "Hide the status text");
  app.add_option("--listen", flags.link.listen,
                 "Serve the Viewer control service (status, snapshot, load scene) on ADDR");
  app.add_option("--listen-tls-cert", flags.link.listen_tls.cert_file,
                 "TLS certificate of --listen")
      ->check(CLI::ExistingFile);
  app.add_option("--listen-tls-key", flags.link.listen_tls.key_file, "TLS key of --listen")
      ->check(CLI::ExistingFile);
  o.web = app.add_option("--web", flags.link.web.address,
                         "Serve the scene to web browsers on HOST:PORT (port 0 = any free "
                         "port; prints 'web on http://HOST:PORT/'), e.g. 127.0.0.1:8080");
  flags.link.web.root = MBSTREAM_WEB_ROOT;
  app.add_option("--web-root", flags.link.web.root,
                 "The web page's folder (index.html, page.js, node_modules/three)")
      ->check(CLI::ExistingDirectory)
      ->needs(o.web);
  app.add_option("--web-max-pages", flags.link.web.max_pages,
                 "Web pages open at once; more are refused (HTTP 503)")
      ->default_val(32)
      ->check(CLI::Range(1, 10000))
      ->needs(o.web);
  std::vector<std::string> web_tls;
  app.add_option("--web-tls", flags.web_tls,
                 "Serve the pages over HTTPS/WSS with this PEM certificate and key: CERT,KEY")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::ExistingFile)
      ->needs(o.web);
}

}  // namespace

void AddViewerFlags(CLI::App& app, ViewerFlags& flags) {
  Related o;
  AddLocalFlags(app, flags, o);
  AddLinkFlags(app, flags, o);
  AddOutputFlags(app, flags, o);
  o.web->needs(o.server);
  o.run->needs(o.server)->excludes(o.follow);
  for (CLI::Option* replay_option : {o.speed, o.loop, o.from_seq, o.paused, o.compare}) {
    replay_option->needs(o.run);
  }
  o.follow->needs(o.server);

  o.check->excludes(o.scene)->excludes(o.model)->excludes(o.pose)->excludes(o.snapshot);
  o.scene->excludes(o.model);
}

std::string FinishViewerFlags(ViewerFlags& flags) {
  const size_t x = flags.size.find('x');
  if (x == std::string::npos || (flags.pose.width = std::atoi(flags.size.c_str())) <= 0 ||
      (flags.pose.height = std::atoi(flags.size.c_str() + x + 1)) <= 0) {
    return "--size '" + flags.size + "' is not WIDTHxHEIGHT, e.g. 640x480";
  }
  if (flags.pose.pose && flags.pose.scene_file.empty() && flags.pose.model_file.empty()) {
    return "--pose needs --scene FILE or --model FILE";
  }
  if (flags.web_tls.size() == 2) {
    flags.link.web.tls_cert_file = flags.web_tls[0];
    flags.link.web.tls_key_file = flags.web_tls[1];
  }
  return "";
}

}  // namespace mbstream::viewer
