// What the viewer is doing, shared by the network thread (writes), the HUD and the control
// service (read).
#pragma once

#include <algorithm>
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
      s.set_mode("live");
      s.set_paused(false);
      s.set_seq(-1);
      s.set_ghost_frames(0);
      s.set_tcp_distance_m(0);
      s.set_tcp_distance_max_m(0);
      s.set_tcp_distance_max_t_s(0);
      compute_ns_total_ = 0;
    });
  }
  // The run's formulation and method (its stats once it ended, else its spec).
  void SetMethod(const std::string& formulation, const std::string& method) {
    Set([&](v1::ViewerStatus& s) {
      s.set_formulation(formulation);
      s.set_method(method);
    });
  }
  // A replay's state (the server's ReplayState).
  void SetReplay(bool paused, double speed, int64_t run_frames, const std::string& compare_run_id,
                 const std::string& probe_set) {
    Set([&](v1::ViewerStatus& s) {
      s.set_mode("replay");
      s.set_paused(paused);
      s.set_speed(speed);
      s.set_run_frames(run_frames);
      s.set_compare_run_id(compare_run_id);
      s.set_probe_set(probe_set);
    });
  }
  void SetSeq(int64_t seq) {
    Set([&](v1::ViewerStatus& s) { s.set_seq(seq); });
  }
  // A ghost frame shown at simulated time t_s, its TCP `distance_m` from the run's.
  void AddGhost(double t_s, double distance_m) {
    Set([&](v1::ViewerStatus& s) {
      s.set_ghost_frames(s.ghost_frames() + 1);
      s.set_tcp_distance_m(distance_m);
      if (distance_m > s.tcp_distance_max_m() || s.ghost_frames() == 1) {
        s.set_tcp_distance_max_m(distance_m);
        s.set_tcp_distance_max_t_s(t_s);
      }
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
  // A frame shown with `count` contacts drawn (--contacts).
  void AddContacts(int count) {
    if (count == 0) return;
    Set([&](v1::ViewerStatus& s) {
      s.set_contact_frames(s.contact_frames() + 1);
      s.set_contacts_peak(std::max(s.contacts_peak(), count));
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
  // Into `out`, whose strings keep their memory (no allocation once they are long enough).
  void Get(v1::ViewerStatus* out) const {
    std::lock_guard<std::mutex> lock(mutex_);
    out->CopyFrom(status_);
  }
  // The newest frame's seq and simulated time alone.
  void GetSeq(int64_t* seq, double* t_s) const {
    std::lock_guard<std::mutex> lock(mutex_);
    *seq = status_.seq();
    *t_s = status_.t_s();
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
