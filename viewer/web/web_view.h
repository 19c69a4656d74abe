// The viewer's scene for web pages: connects the render loop (a new scene: exported once
// per model), the subscriber link (each posed batch: its newest pose, probes and the run's
// state) and the page's replay controls (to the link's stream) to the WebServer.
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "mbstream/v1/replay.pb.h"
#include "viewer/link/link_status.h"
#include "viewer/scene/scene.h"
#include "viewer/web/web_server.h"

namespace mbstream::viewer {

class WebView {
 public:
  using SendControl = std::function<bool(const v1::ReplayControl&)>;
  // Binds (throws std::runtime_error, as WebServer). `send_control` may be empty (live runs:
  // the page's controls are refused).
  WebView(WebOptions options, const LinkStatus* status, SendControl send_control);

  std::string url() const { return server_.url(); }
  void Start() { server_.Start(); }
  void Stop() { server_.Stop(); }

  // Render thread, when the viewer's scene changed (null: none).
  void OnScene(Scene* scene);
  // The link's thread, after it posed `scene` for a batch of frames (the status is updated).
  void OnPosed(Scene& scene, std::span<const ProbeReport> probes);
  // Render thread, every draw: sends the state again when it changed without a pose (a run
  // ended, a replay paused).
  void OnTick();

  // A page's control as JSON ({"pause":true}, {"resume":true}, {"seek_seq":N}, {"step":N},
  // {"speed":X}) -> the replay control; false when it is not one.
  static bool ParseControl(const std::string& json, v1::ReplayControl* control);

 private:
  // Under mutex_: the frame message of the cached pose, published.
  void PublishLocked();

  const LinkStatus* status_;
  SendControl send_control_;
  WebServer server_;

  std::mutex mutex_;  // guards everything below
  const Scene* scene_ = nullptr;
  std::uint64_t version_ = 0;
  std::uint64_t number_ = 0;
  std::vector<Eigen::Isometry3d> frames_, ghost_frames_;
  std::vector<ProbeReport> probes_;
  std::string published_state_;  // what OnTick compares
};

}  // namespace mbstream::viewer
