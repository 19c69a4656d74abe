#include "viewer/link/scene_slot.h"

#include <exception>

namespace mbstream::viewer {

std::string SceneSlot::Replace(SceneDescription description) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (shut_down_) return "the viewer is stopping";
  pending_ = std::move(description);
  const int64_t ticket = ++requests_;
  done_.wait(lock, [&] { return served_ >= ticket || shut_down_; });
  if (served_ < ticket) return "the viewer is stopping";
  return pending_error_;
}

void SceneSlot::RunOnRenderThread(std::function<void(Scene*)> task) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (shut_down_) return;
  tasks_.push_back(std::move(task));
  const int64_t ticket = ++tasks_queued_;
  done_.wait(lock, [&] { return tasks_done_ >= ticket || shut_down_; });
}

Scene* SceneSlot::Service(vtkRenderWindow* window, bool* changed) {
  *changed = false;
  if (!window && scene_ && scene_->render_window()) scene_->ForgetWindow();
  std::optional<SceneDescription> request;
  std::deque<std::function<void(Scene*)>> tasks;
  int64_t ticket = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    request.swap(pending_);
    ticket = requests_;
    tasks.swap(tasks_);
  }
  if (request) {
    std::string error;
    try {
      auto scene = std::make_unique<Scene>(std::move(*request), options_, window);
      std::unique_ptr<Scene> old;
      {
        std::lock_guard<std::mutex> lock(scene_mutex_);
        old = std::move(scene_);
        scene_ = std::move(scene);
      }
      old.reset();  // destroyed here, on the render thread
      *changed = true;
    } catch (const std::exception& e) {
      error = e.what();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    pending_error_ = error;
    served_ = ticket;
    done_.notify_all();
  }
  Scene* current = scene_.get();  // only this thread replaces it
  if (!tasks.empty()) {
    for (auto& task : tasks) task(current);
    std::lock_guard<std::mutex> lock(mutex_);
    tasks_done_ += static_cast<int64_t>(tasks.size());
    done_.notify_all();
  }
  return current;
}

void SceneSlot::Shutdown() {
  std::lock_guard<std::mutex> lock(mutex_);
  shut_down_ = true;
  done_.notify_all();
}

}  // namespace mbstream::viewer
