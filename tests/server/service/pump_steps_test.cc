// PumpSteps (server/service/pump_steps.h): a reactor's turns never overlap; work asked for
// while a turn runs is done by that turn, once more, before it ends; steps asked for are
// taken once.
#include "server/service/pump_steps.h"

#include <gtest/gtest.h>

#include <future>
#include <mutex>
#include <thread>

namespace mbstream {
namespace {

TEST(PumpStepsTest, ATurnAskedForDuringAPassMakesThatTurnPassOnceMore) {
  std::mutex mutex;
  std::unique_lock<std::mutex> lock(mutex);
  PumpSteps steps;
  int passes = 0, nested = 0;
  steps.Turn([&] {
    ++passes;
    if (passes == 1) {
      // A reaction run inline (the same thread, the turn still running): no nested pass.
      steps.Turn([&] { ++nested; });
      steps.Turn([&] { ++nested; });  // two asks, one more pass
    }
  });
  EXPECT_EQ(passes, 2);
  EXPECT_EQ(nested, 0);
  steps.Turn([&] { ++passes; });  // the turn ended: the next one runs at once
  EXPECT_EQ(passes, 3);
}

TEST(PumpStepsTest, AnotherThreadsTurnIsTakenOverByTheRunningOne) {
  std::mutex mutex;
  PumpSteps steps;
  std::promise<void> outside, asked;
  int passes = 0;
  bool other_ran = false;
  std::thread other;
  {
    std::unique_lock<std::mutex> lock(mutex);
    steps.Turn([&] {
      if (++passes > 1) return;
      // As around gRPC's StartWrite: the lock is released while the pass runs on.
      lock.unlock();
      other = std::thread([&] {
        std::lock_guard<std::mutex> other_lock(mutex);
        steps.Turn([&] { other_ran = true; });  // returns at once: a turn is running
        asked.set_value();
      });
      asked.get_future().wait();
      lock.lock();
    });
  }
  other.join();
  EXPECT_EQ(passes, 2);
  EXPECT_FALSE(other_ran);
}

TEST(PumpStepsTest, AStepAskedForIsTakenOnce) {
  PumpSteps steps;
  EXPECT_FALSE(steps.TakeWanted());
  steps.Want();
  steps.Want();
  EXPECT_TRUE(steps.TakeWanted());
  EXPECT_FALSE(steps.TakeWanted());
}

}  // namespace
}  // namespace mbstream
