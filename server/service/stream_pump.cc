#include "server/service/stream_pump.h"

#include <spdlog/spdlog.h>

#include <exception>

namespace mbstream {

StreamPump::StreamPump(int threads) {
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { Work(); });
}

StreamPump::~StreamPump() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  for (std::thread& thread : threads_) thread.join();
  tasks_.clear();  // outside the threads: a task's captures may end a reactor's life
}

void StreamPump::PostAt(Clock::time_point due, std::function<void()> task) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool first = tasks_.empty() || due < tasks_.begin()->first;
    tasks_.emplace(due, std::move(task));
    if (!first) return;  // the threads wait for an earlier task already
  }
  changed_.notify_one();
}

void StreamPump::Work() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    if (tasks_.empty()) {
      changed_.wait(lock);
      continue;
    }
    const Clock::time_point due = tasks_.begin()->first;
    if (due > Clock::now()) {
      changed_.wait_until(lock, due);
      continue;
    }
    std::function<void()> task = std::move(tasks_.begin()->second);
    tasks_.erase(tasks_.begin());
    if (!tasks_.empty()) changed_.notify_one();  // another thread may take the next one
    lock.unlock();
    try {
      task();
    } catch (const std::exception& error) {
      spdlog::error("stream task failed: {}", error.what());
    }
    task = nullptr;  // its captures go before the lock is taken again
    lock.lock();
  }
}

}  // namespace mbstream
