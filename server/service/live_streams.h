// The service's open streaming reactors, so that a server shutting down can wake each one
// (it then sends `closing` or ends with UNAVAILABLE). Thread-safe.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace mbstream {

// A reactor that can be told to look at its state again (from any thread; never blocks).
class Pokeable {
 public:
  virtual ~Pokeable() = default;
  virtual void Poke() = 0;
};

class LiveStreams {
 public:
  using Id = uint64_t;
  Id Add(std::weak_ptr<Pokeable> stream) {
    std::lock_guard<std::mutex> lock(mutex_);
    streams_.emplace(++last_, std::move(stream));
    return last_;
  }
  void Remove(Id id) {
    std::lock_guard<std::mutex> lock(mutex_);
    streams_.erase(id);
  }
  void PokeAll() {
    std::vector<std::shared_ptr<Pokeable>> open;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& [id, stream] : streams_) {
        if (std::shared_ptr<Pokeable> alive = stream.lock()) open.push_back(std::move(alive));
      }
    }
    for (const auto& stream : open) stream->Poke();
  }

 private:
  std::mutex mutex_;
  std::map<Id, std::weak_ptr<Pokeable>> streams_;
  Id last_ = 0;
};

}  // namespace mbstream
