// mbstream-viewer --server ADDR (--run ID | --follow): the network thread subscribes and
// answers probes; this (main) thread renders; --listen serves the Viewer control service.
#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include <pthread.h>

#include <csignal>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <thread>

#include "shared/net/server_credentials.h"
#include "shared/net/tls_files.h"
#include "viewer/app/commands.h"
#include "viewer/app/scene_loading.h"
#include "viewer/link/render_loop.h"
#include "viewer/link/subscriber_link.h"
#include "viewer/link/viewer_control_service.h"
#include "viewer/scene/scene_error.h"
#include "viewer/scene/view_window.h"
#include "viewer/web/page_access.h"
#include "viewer/web/web_view.h"

namespace mbstream::viewer {

namespace {

constexpr double kGhostOpacity = 0.35;  // --compare: the ghost's opacity

// SIGINT and SIGTERM handled by a thread of their own (sigwait), as the server does: a signal
// handler may not call into gRPC (cancelling a call takes its locks, and the signal may
// interrupt a thread holding them: the viewer then aborted now and then on SIGTERM). Built
// before any other thread starts, so that every thread inherits the blocked mask; SIGUSR2
// (thread-directed, from the destructor) ends the waiter when the link ended by itself.
class SignalStopper {
 public:
  SignalStopper() {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    sigaddset(&signals_, SIGUSR2);
    pthread_sigmask(SIG_BLOCK, &signals_, nullptr);
  }
  ~SignalStopper() { Finish(); }
  SignalStopper(const SignalStopper&) = delete;
  SignalStopper& operator=(const SignalStopper&) = delete;

  // Calls `stop` (on the waiter thread) at the first SIGINT or SIGTERM.
  void Start(std::function<void()> stop) {
    waiter_ = std::thread([this, stop = std::move(stop)] {
      int signal = 0;
      if (sigwait(&signals_, &signal) == 0 && signal != SIGUSR2) {
        spdlog::info("{} received: stopping", signal == SIGINT ? "SIGINT" : "SIGTERM");
        stop();
      }
    });
  }
  // Ends the waiter (once this returns, `stop` is not called any more).
  void Finish() {
    if (!waiter_.joinable()) return;
    pthread_kill(waiter_.native_handle(), SIGUSR2);  // harmless if it already returned
    waiter_.join();
  }

 private:
  sigset_t signals_;
  std::thread waiter_;
};

bool HasDisplay() {
  const char* display = std::getenv("DISPLAY");
  return display && *display;
}

// The Viewer control service and its gRPC server, when --listen is given.
struct ControlServer {
  std::unique_ptr<ViewerControlService> service;
  std::unique_ptr<grpc::Server> server;
};

// The Viewer control service on options.listen (nothing when it is empty). False, said on
// stderr, when it cannot listen there.
bool StartControl(const LinkCommandOptions& options, SceneSlot* slot, LinkStatus* status,
                  SubscriberLink& link, ControlServer& control) {
  if (options.listen.empty()) return true;
  control.service = std::make_unique<ViewerControlService>(
      slot, status, [&link](const v1::ReplayControl& c) { return link.SendControl(c); });
  grpc::ServerBuilder builder;
  int port = 0;
  try {
    builder.AddListeningPort(options.listen, net::MakeServerCredentials(options.listen_tls), &port);
  } catch (const net::SecurityConfigError& e) {
    std::cerr << "mbstream-viewer: " << e.what() << "\n";
    return false;
  }
  builder.RegisterService(control.service.get());
  control.server = builder.BuildAndStart();
  if (!control.server) {
    std::cerr << "mbstream-viewer: cannot listen on " << options.listen << "\n";
    return false;
  }
  const std::string address =
      options.listen.rfind("unix:", 0) == 0
          ? options.listen
          : options.listen.substr(0, options.listen.rfind(':') + 1) + std::to_string(port);
  std::cout << "control service listening on " << address << std::endl;
  return true;
}

// The web view on options.web.address (null when it is empty), fed by the link's poses.
// False, said on stderr, when it cannot start.
bool StartWeb(const LinkCommandOptions& options, LinkStatus* status, SubscriberLink& link,
              std::unique_ptr<WebView>& web) {
  if (options.web.address.empty()) return true;
  WebView::SendControl send;
  if (!options.link.follow) {
    send = [&link](const v1::ReplayControl& c) { return link.SendControl(c); };
  }
  try {
    // Pages need the server's view role; steering a replay (every page's and the window's)
    // needs its run role.
    WebOptions web_options = options.web;
    auto access = std::make_shared<PageAccess>(options.link.server, options.link.security,
                                               !options.link.follow);
    web_options.check_access = [access](const std::string& token, auto done) {
      access->Check(token, std::move(done));
    };
    web = std::make_unique<WebView>(std::move(web_options), status, std::move(send));
  } catch (const std::exception& e) {
    std::cerr << "mbstream-viewer: " << e.what() << "\n";
    return false;
  }
  WebView* view = web.get();
  link.SetPosedListener(
      [view](Scene& scene, std::span<const ProbeReport> probes) { view->OnPosed(scene, probes); });
  web->Start();
  std::cout << "web on " << web->url() << std::endl;
  return true;
}

// The last status, logged as the viewer ends.
void LogFinalStatus(const LinkStatus& status) {
  const v1::ViewerStatus final = status.Get();
  spdlog::info("viewer done: {} runs, last run {}: {} frames, {} probe reports", final.runs_seen(),
               final.run_id(), final.frames(), final.probe_reports());
  if (final.contact_frames() > 0) {
    spdlog::info("contacts: drawn in {} frames, at most {} in one", final.contact_frames(),
                 final.contacts_peak());
  }
  if (final.mode() == "replay") {
    spdlog::info("replay of run {}: probe set {}", final.run_id(), final.probe_set());
  }
  if (!final.compare_run_id().empty()) {
    spdlog::info(
        "compare {} with ghost {}: {} ghost frames, max |TCP - ghost TCP| {:.17g} m at "
        "t = {:.17g} s",
        final.run_id(), final.compare_run_id(), final.ghost_frames(), final.tcp_distance_max_m(),
        final.tcp_distance_max_t_s());
  }
}

}  // namespace

int RunLink(const LinkCommandOptions& options) {
  if (!HasDisplay()) {
    std::cerr << "no X display (DISPLAY is not set): run under Xvfb with --offscreen, e.g. "
                 "xvfb-run -a mbstream-viewer --server ADDR --follow --offscreen\n";
    return 2;
  }
  SignalStopper signals;  // first: before any thread (gRPC's, VTK's, ours) starts
  RunSceneSource scenes;
  scenes.asset_root =
      std::filesystem::temp_directory_path() / ("mbstream-viewer-" + std::to_string(getpid()));
  if (!options.scene_file.empty() || !options.model_file.empty()) {
    scenes.override_scene = LoadScene(options.scene_file, options.model_file, options.asset_dirs,
                                      options.package_paths, options.floating_base);
    if (!scenes.override_scene) return 1;
  }
  SceneOptions scene_options;
  scene_options.width = options.width;
  scene_options.height = options.height;
  scene_options.offscreen = options.offscreen;
  scene_options.triangle_budget = options.triangle_budget;
  scene_options.window_title = "mbstream viewer: " + options.link.server;
  if (!options.link.replay.compare_run_id.empty()) scene_options.ghost_opacity = kGhostOpacity;
  scene_options.contacts = options.link.contacts;
  scene_options.contact_scale = options.link.contact_scale;
  LinkOptions link_options = options.link;
  if (!options.scene_file.empty()) {
    link_options.replay.scene_tag = std::filesystem::path(options.scene_file).filename().string();
  }
  // One window on one X connection for the viewer's life (view_window.h), whatever the runs.
  std::optional<ViewWindow> view;
  try {
    view.emplace(scene_options);
  } catch (const SceneError& e) {
    std::cerr << "mbstream-viewer: " << e.what() << "\n";
    return 2;
  }
  SceneSlot slot(scene_options);
  LinkStatus status;

  // Built first (it starts streaming in Run()): the control service sends through it.
  SubscriberLink link(link_options, std::move(scenes), &slot, &status);
  ControlServer control;
  if (!StartControl(options, &slot, &status, link, control)) return 1;
  std::unique_ptr<WebView> web;
  if (!StartWeb(options, &status, link, web)) return 1;

  signals.Start([&link] { link.Stop(); });
  std::atomic<bool> stop{false};
  int exit_code = 0;
  std::thread network([&] {
    exit_code = link.Run();
    stop = true;
  });
  RenderOptions render = options.render;
  render.interactive = !options.offscreen;
  if (!options.link.follow) {
    render.send_control = [&link](const v1::ReplayControl& c) { return link.SendControl(c); };
  }
  if (web) {
    render.on_scene_changed = [&web](Scene* scene) { web->OnScene(scene); };
    render.on_tick = [&web] { web->OnTick(); };
  }
  RunRenderLoop(&*view, &slot, &status, render, stop);
  network.join();
  if (web) web->Stop();
  signals.Finish();  // before `link` goes
  if (control.server) control.server->Shutdown();
  std::error_code ignored;
  std::filesystem::remove_all(
      std::filesystem::temp_directory_path() / ("mbstream-viewer-" + std::to_string(getpid())),
      ignored);
  LogFinalStatus(status);
  return exit_code;
}

}  // namespace mbstream::viewer
