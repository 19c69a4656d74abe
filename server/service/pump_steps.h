// How a streaming reactor's work is scheduled (subscribe_call.h, watch_call.h). Its work comes
// in turns: a turn is one thread's run of the reactor's "pass" (its sender's step, when one was
// asked for, then its gRPC operations: StartRead, StartWrite, Finish). Turns of one reactor
// never overlap: whoever wants work done (a gRPC reaction, a pump task, a deadline) takes the
// reactor's lock and asks for a turn; when another thread's turn is running, that turn passes
// once more instead, before it ends. So one thread at a time starts gRPC operations, at most
// one write is in flight (StreamWrites), and every gRPC operation of a call is ordered after
// the previous one through the reactor's lock (ThreadSanitizer sees that order; it cannot see
// gRPC's own). Steps are asked for soon (Poke, on the pump) or at a time (WakeAt).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>

#include "server/service/stream_pump.h"

namespace mbstream {

// A member of the reactor; all but Poke with the reactor's lock held.
class PumpSteps {
 public:
  // Any thread, lock held or not: self->RunStep() soon, on the pump (pokes while one is
  // pending are one). RunStep asks for a step (Want) and a turn. `self` keeps the reactor
  // alive until then.
  template <typename Reactor>
  void Poke(StreamPump& pump, std::shared_ptr<Reactor> self) {
    if (poke_pending_.exchange(true)) return;
    pump.Post([this, self = std::move(self)] {
      poke_pending_ = false;
      self->RunStep();
    });
  }
  // self->RunStep() at `due`; only the latest time asked for counts.
  template <typename Reactor>
  void WakeAt(StreamPump& pump, StreamPump::Clock::time_point due, std::shared_ptr<Reactor> self,
              std::mutex& mutex) {
    const uint64_t wake = ++wake_;
    pump.PostAt(due, [this, self = std::move(self), wake, &mutex] {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (wake != wake_) return;  // a later step asked for another time
      }
      self->RunStep();
    });
  }

  void Want() { step_wanted_ = true; }  // the next pass steps the sender
  // In a pass: whether a step was asked for since the last one (and no longer).
  bool TakeWanted() { return std::exchange(step_wanted_, false); }

  // Runs `pass` now, and again while more was asked for meanwhile, unless another thread's
  // turn is running: that one then passes once more. `pass` may release the lock and take
  // it again (around gRPC's calls); it must not throw.
  template <typename Pass>
  void Turn(Pass pass) {
    if (running_) {
      again_ = true;
      return;
    }
    running_ = true;
    do {
      again_ = false;
      pass();
    } while (again_);
    running_ = false;
  }

 private:
  std::atomic<bool> poke_pending_{false};
  uint64_t wake_ = 0;  // the latest WakeAt
  bool step_wanted_ = false;
  bool running_ = false;  // a turn runs (on some thread)
  bool again_ = false;    // something came during the running turn's pass
};

}  // namespace mbstream
