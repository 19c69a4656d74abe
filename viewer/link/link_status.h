// What the viewer is doing, shared by the network thread (writes), the HUD and the control
// service (read).
#pragma once

#include <mutex>
#include <string>

#include "mbstream/v1/viewer_service.pb.h"

namespace mbstream::viewer {

class LinkStatus {
 public:
  void SetServer(const std::string& server) {
    Set([&](v1::ViewerStatus& s) { s.set_server(server); });
  }
  void SetState(const std::string& state) {
    Set([&](v1::ViewerStatus& s) { s.set_state(state); });
  }

  // A new run: clears the per-run counters.
  void StartRun(const std::string& run_id, const std::string& model_id, const std::string& title,
                int dofs) {
    Set([&](v1::ViewerStatus& s) {
      s.set_state("running");
      s.set_run_id(run_id);
      s.set_model_id(model_id);
      s.set_scene_title(title);
      s.set_dofs(dofs);
      s.set_t_s(0);
      s.set_frames(0);
      s.set_missed_frames(0);
      s.set_probe_reports(0);
      s.set_runs_seen(s.runs_seen() + 1);
      compute_ns_total_ = 0;
    });
  }
  void AddFrames(double t_s, int frames, int64_t missed, int probes, int64_t compute_ns) {
    Set([&](v1::ViewerStatus& s) {
      compute_ns_total_ += compute_ns;
      s.set_t_s(t_s);
      s.set_frames(s.frames() + frames);
      s.set_missed_frames(s.missed_frames() + missed);
      s.set_probe_reports(s.probe_reports() + probes);
      s.set_probe_compute_us(s.frames() > 0 ? 1e-3 * compute_ns_total_ / s.frames() : 0.0);
    });
  }
  // Frames the server dropped for this viewer with no frame of the batch left to show.
  void AddMissed(int64_t missed) {
    Set([&](v1::ViewerStatus& s) { s.set_missed_frames(s.missed_frames() + missed); });
  }
  void SetRenderFps(double fps) {
    Set([&](v1::ViewerStatus& s) { s.set_render_fps(fps); });
  }

  v1::ViewerStatus Get() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }

 private:
  template <typename Change>
  void Set(Change change) {
    std::lock_guard<std::mutex> lock(mutex_);
    change(status_);
  }
  mutable std::mutex mutex_;
  v1::ViewerStatus status_;
  int64_t compute_ns_total_ = 0;  // this run's probe computation time, guarded by mutex_
};

}  // namespace mbstream::viewer
