// The current Scene, owned by the render thread; other threads ask for a new one and use
// the current one's thread-safe pose side.
//
// VTK objects must be created and destroyed on the render thread, so a request from the
// network thread (a new run's scene) or the control service (LoadScene) is built there;
// the requester waits until it is.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "viewer/scene/scene.h"

namespace mbstream::viewer {

class SceneSlot {
 public:
  explicit SceneSlot(SceneOptions options) : options_(std::move(options)) {}

  // Any thread but the render thread: replaces the scene; returns "" or why it failed.
  std::string Replace(SceneDescription description);

  // Any thread: runs `use` on the current scene's pose side under the slot's lock; returns
  // false when there is no scene.
  template <typename Use>
  bool WithScene(Use use) {
    std::lock_guard<std::mutex> lock(scene_mutex_);
    if (!scene_) return false;
    use(*scene_);
    return true;
  }

  // Any thread: runs `task` on the render thread with the current scene (or nullptr) and
  // waits for it.
  void RunOnRenderThread(std::function<void(Scene*)> task);

  // Render thread: builds a requested scene into `window` (the viewer's one window; null once
  // its display is lost, and then the current scene forgets the window it had) and runs
  // queued tasks; returns the current scene (or nullptr) and whether it changed since the
  // last call.
  Scene* Service(vtkRenderWindow* window, bool* changed);

  // Wakes and fails every waiter; later requests fail at once.
  void Shutdown();
  // Render thread, at the end: destroys the scene.
  void DestroyScene() {
    std::lock_guard<std::mutex> lock(scene_mutex_);
    scene_.reset();
  }

 private:
  SceneOptions options_;
  std::mutex scene_mutex_;  // guards scene_ against replacement while a thread poses it
  std::unique_ptr<Scene> scene_;

  std::mutex mutex_;
  std::condition_variable done_;
  std::optional<SceneDescription> pending_;
  std::string pending_error_;
  int64_t requests_ = 0, served_ = 0;
  std::deque<std::function<void(Scene*)>> tasks_;
  int64_t tasks_queued_ = 0, tasks_done_ = 0;
  bool shut_down_ = false;
};

}  // namespace mbstream::viewer
