// The viewer's render thread (the main thread): builds scenes on request, draws the newest
// pose into the viewer's one window at a fixed display rate with a HUD, records video and
// PNG snapshots. Probes never wait for it: the network thread computes them from the scene's
// pose side.
#pragma once

#include <atomic>
#include <functional>
#include <string>

#include "mbstream/v1/replay.pb.h"
#include "viewer/link/link_status.h"
#include "viewer/link/scene_slot.h"
#include "viewer/scene/view_window.h"

namespace mbstream::viewer {

struct RenderOptions {
  double fps = 20.0;          // draws per second (the video's frame rate)
  std::string record_file;    // .ogv; empty = no video
  std::string snapshots_dir;  // PNG every `snapshot_every` draws; empty = none
  int snapshot_every = 20;
  bool hud = true;
  bool interactive = false;  // window mode: mouse interaction (trackball camera)
  // Window mode of a replay: its time controls (replay_keys.h) send through this.
  std::function<bool(const v1::ReplayControl&)> send_control;
  // Called every tick on this thread: with the scene when it changed (null: none), and once
  // per tick after drawing (--web: web_view.h).
  std::function<void(Scene*)> on_scene_changed;
  std::function<void()> on_tick;
};

// Runs until `stop` is set; returns after finishing the video. Every scene draws into
// `view`'s one window; the scene is destroyed here (before `view`). Once `view`'s display is
// lost nothing is drawn, recorded or snapshotted, and scenes are still built for the link.
void RunRenderLoop(ViewWindow* view, SceneSlot* slot, LinkStatus* status,
                   const RenderOptions& options, const std::atomic<bool>& stop);

}  // namespace mbstream::viewer
