#include "viewer/link/render_loop.h"

#include <spdlog/spdlog.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkNew.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>

#include "viewer/link/replay_keys.h"
#include "viewer/link/video_recorder.h"
#include "viewer/scene/kept_for_good.h"

namespace mbstream::viewer {

namespace {

using Clock = std::chrono::steady_clock;

std::string HudText(const v1::ViewerStatus& s) {
  char text[256];
  std::snprintf(text, sizeof(text),
                "run %s  %s\nt = %.3f s   frames %lld (missed %lld)\nrender %.1f fps   "
                "probe %.1f us",
                s.run_id().empty() ? "-" : s.run_id().c_str(), s.state().c_str(), s.t_s(),
                static_cast<long long>(s.frames()), static_cast<long long>(s.missed_frames()),
                s.render_fps(), s.probe_compute_us());
  std::string hud = text;
  if (!s.formulation().empty() || !s.method().empty()) {
    hud += "\n" + s.formulation() + " / " + s.method();
  }
  if (s.mode() == "replay") {
    std::snprintf(text, sizeof(text), "\nreplay  %s  x%g  frame %lld of %lld",
                  s.paused() ? "paused" : "playing", s.speed(), static_cast<long long>(s.seq()),
                  static_cast<long long>(s.run_frames()));
    hud += text;
  }
  if (!s.compare_run_id().empty()) {
    std::snprintf(text, sizeof(text), "\nghost %s  |TCP - ghost| %.3g mm  max %.3g mm (t = %.2f s)",
                  s.compare_run_id().c_str(), 1e3 * s.tcp_distance_m(),
                  1e3 * s.tcp_distance_max_m(), s.tcp_distance_max_t_s());
    hud += text;
  }
  return hud;
}

}  // namespace

void RunRenderLoop(ViewWindow* view, SceneSlot* slot, LinkStatus* status,
                   const RenderOptions& options, const std::atomic<bool>& stop) {
  std::unique_ptr<VideoRecorder> recorder;
  if (!options.record_file.empty()) {
    recorder = std::make_unique<VideoRecorder>(options.record_file, static_cast<int>(options.fps));
  }
  if (!options.snapshots_dir.empty()) std::filesystem::create_directories(options.snapshots_dir);
  vtkNew<vtkTextActor> hud;
  hud->GetTextProperty()->SetFontSize(14);
  hud->GetTextProperty()->SetColor(1.0, 1.0, 0.6);
  hud->SetDisplayPosition(10, 10);

  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options.fps));
  Clock::time_point next = Clock::now();
  Clock::time_point fps_window = next;
  // Window mode: one interactor on the one window, made with the first scene; its pending
  // mouse/keyboard events are handled every tick (ProcessEvents), so the user can turn the
  // camera while frames keep coming.
  vtkSmartPointer<vtkRenderWindowInteractor> interactor;
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  std::unique_ptr<ReplayKeys> keys;
  int draws = 0, window_draws = 0, snapshots = 0;
  while (!stop) {
    // Once the display is lost nothing draws: scenes are still built (without a window), so
    // the link goes on posing them and answering probes.
    const bool drawing = view->Check(/*discard_events=*/!options.interactive);
    bool changed = false;
    Scene* scene = slot->Service(view->window(), &changed);
    if (changed && options.on_scene_changed) options.on_scene_changed(scene);
    if (!drawing) scene = nullptr;
    if (scene && changed && options.hud) scene->renderer()->AddActor2D(hud);
    if (scene && changed && options.interactive) {
      if (!interactor) {
        interactor = vtkSmartPointer<vtkRenderWindowInteractor>::New();
        interactor->SetInteractorStyle(style);
        interactor->SetRenderWindow(view->window());
        interactor->Initialize();
      }
      if (options.send_control) {  // the slider goes into the new scene's renderer
        keys.reset();
        keys = std::make_unique<ReplayKeys>(options.send_control, status);
        keys->Install(interactor);
      }
    }
    if (keys && drawing) keys->Update();
    if (interactor && drawing) interactor->ProcessEvents();
    if (scene) {
      if (options.hud) hud->SetInput(HudText(status->Get()).c_str());
      scene->Render();
    }
    if (scene && !view->lost()) {  // (a render may be what finds the display gone)
      ++draws;
      ++window_draws;
      if (recorder) recorder->AddFrame(scene->render_window());
      // The first draw, then every snapshot_every-th (also when it is 1).
      if (!options.snapshots_dir.empty() && (draws - 1) % options.snapshot_every == 0) {
        char name[64];
        std::snprintf(name, sizeof(name), "frame_%05d.png", ++snapshots);
        try {
          scene->SnapshotPng(std::filesystem::path(options.snapshots_dir) / name);
        } catch (const std::exception& e) {
          spdlog::error("snapshot: {}", e.what());
        }
      }
    }
    if (options.on_tick) options.on_tick();
    const Clock::time_point now = Clock::now();
    if (now - fps_window >= std::chrono::seconds(1)) {
      status->SetRenderFps(window_draws / std::chrono::duration<double>(now - fps_window).count());
      fps_window = now;
      window_draws = 0;
    }
    next += period;
    if (next < now) next = now;  // never try to catch up a backlog of draws
    std::this_thread::sleep_until(next);
  }
  slot->Shutdown();
  if (recorder) recorder->End();
  if (view->lost()) {  // left alive: freeing them would talk to the lost X server
    KeepForGood(keys.release());
    if (interactor) interactor->Register(nullptr);
    KeepForGood(interactor.Get());
  }
  keys.reset();
  interactor = nullptr;
  slot->DestroyScene();
}

}  // namespace mbstream::viewer
