// Store: calls from several threads at once all land and never interfere.
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using testing::MakeBundle;
using testing::MakeFrames;
using testing::MakeModelInfo;
using testing::MakeProbe;
using testing::MakeRun;
using testing::TempDirectory;

class StoreConcurrencyTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreConcurrencyTest);

TEST_P(StoreConcurrencyTest, ManyThreadsWriteAndRead) {
  constexpr int kThreads = 6;
  constexpr int kRunsPerThread = 8;
  auto store = Open();
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&store, t] {
      // Every thread submits the same model: exactly one copy is stored.
      store->PutModel(MakeModelInfo("m-shared", 100), MakeBundle("shared", 1));
      for (int r = 0; r < kRunsPerThread; ++r) {
        const std::string id = "r-" + std::to_string(t) + "-" + std::to_string(r);
        store->PutRun(MakeRun(id, v1::RUNNING, 1000 + r));
        store->AddProbes({MakeProbe(id, 0, "tip"), MakeProbe(id, 1, "tip")});
        (void)store->ListRuns();
        store->FinishRun(MakeRun(id, v1::FINISHED, 1000 + r), MakeFrames(50 + r, 6));
        EXPECT_EQ(store->GetFrames(id).size(), static_cast<std::size_t>(50 + r));
        EXPECT_EQ(store->GetRun(id)->state(), v1::FINISHED);
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(store->ListModels().size(), 1u);
  const auto runs = store->ListRuns();
  ASSERT_EQ(runs.size(), static_cast<std::size_t>(kThreads * kRunsPerThread));
  for (const auto& run : runs) {
    EXPECT_EQ(run.state(), v1::FINISHED);
    EXPECT_EQ(store->GetProbes(run.id()).size(), 2u);
  }
  EXPECT_EQ(store->MarkUnfinishedRunsInterrupted("restart"), 0);
}

}  // namespace
}  // namespace mbstream
