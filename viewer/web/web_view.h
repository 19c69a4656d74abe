// The viewer's scene for web pages: connects the render loop (a new scene: exported once
// per model), the subscriber link (each posed batch: its newest pose, probes and the run's
// state) and the page's replay controls (to the link's stream) to the WebServer.
//
// The link's thread (which answers the probes) and the render thread only keep the newest
// pose and ask the web thread for a message; the web thread encodes it (FrameMessageJson) and
// writes it to the pages, so what the pages cost lands on the web thread alone. Poses that
// arrive while a message is waiting to be encoded are folded into it (the pages get the
// newest, as they would from the WebServer's own replacement).
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

  ~WebView() { server_.Stop(); }  // before the fields its thread reads go

  std::string url() const { return server_.url(); }
  void Start() { server_.Start(); }
  void Stop() { server_.Stop(); }

  // Render thread, when the viewer's scene changed (null: none). Exports the scene (VTK's
  // actors are read on their thread).
  void OnScene(Scene* scene);
  // The link's thread, after it posed `scene` for a batch of frames (the status is updated):
  // copies the pose and probes, no encoding, no sending.
  void OnPosed(Scene& scene, std::span<const ProbeReport> probes);
  // Render thread, every draw: the web thread sends the state again when it changed without
  // a pose (a run ended, a replay paused).
  void OnTick();

  // A page's control as JSON ({"pause":true}, {"resume":true}, {"seek_seq":N}, {"step":N},
  // {"speed":X}) -> the replay control; false when it is not one.
  static bool ParseControl(const std::string& json, v1::ReplayControl* control);

 private:
  // Under mutex_: asks the web thread for a message (once until it runs); `posed` when the
  // pose changed (else it is sent only when the state did).
  void RequestLocked(bool posed);
  // The web thread: the newest pose's message, encoded and published.
  void Publish();

  const LinkStatus* status_;
  SendControl send_control_;
  WebServer server_;

  std::mutex mutex_;  // guards everything below up to message_
  const Scene* scene_ = nullptr;
  std::uint64_t version_ = 0;
  std::vector<Eigen::Isometry3d> frames_, ghost_frames_;
  bool contacts_on_ = false;  // the scene draws contacts (--contacts)
  std::vector<ContactMark> contacts_;
  double contact_scale_ = 0.0;
  std::vector<ProbeReport> probes_;
  double posed_unix_ms_ = 0;
  std::int64_t seq_ = -1;  // the status's seq and time when the pose was taken
  double t_s_ = 0;
  bool requested_ = false;  // a Publish is queued on the web thread
  bool posed_ = false;      // the pose changed since the last message

  // The web thread's own (no lock): the message's copy of the pose, the state last sent.
  std::uint64_t number_ = 0;
  std::vector<Eigen::Isometry3d> sent_frames_, sent_ghost_frames_;
  std::vector<ContactMark> sent_contacts_;
  std::vector<ProbeReport> sent_probes_;
  v1::ViewerStatus status_copy_;
  std::string published_state_;
};

}  // namespace mbstream::viewer
