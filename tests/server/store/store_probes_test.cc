// Store: probe reports round trip sorted by (seq, probe); duplicates replace.
#include <gtest/gtest.h>

#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using testing::MakeProbe;
using testing::Same;
using testing::TempDirectory;

class StoreProbesTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreProbesTest);

TEST_P(StoreProbesTest, RoundTripSortedBySeqThenProbe) {
  auto store = Open();
  store->AddProbes({MakeProbe("r-1", 2, "tip"), MakeProbe("r-1", 1, "tip"),
                    MakeProbe("r-1", 1, "elbow"), MakeProbe("r-2", 0, "tip")});
  store->AddProbes({MakeProbe("r-1", 0, "tip")});
  store->AddProbes({});
  const auto probes = store->GetProbes("r-1");
  ASSERT_EQ(probes.size(), 4u);
  EXPECT_TRUE(Same(probes[0], MakeProbe("r-1", 0, "tip")));
  EXPECT_TRUE(Same(probes[1], MakeProbe("r-1", 1, "elbow")));
  EXPECT_TRUE(Same(probes[2], MakeProbe("r-1", 1, "tip")));
  EXPECT_TRUE(Same(probes[3], MakeProbe("r-1", 2, "tip")));
  EXPECT_EQ(store->GetProbes("r-2").size(), 1u);
  EXPECT_TRUE(store->GetProbes("r-missing").empty());
}

TEST_P(StoreProbesTest, DuplicateReplacesOldRow) {
  auto store = Open();
  store->AddProbes({MakeProbe("r-1", 5, "tip")});
  v1::ProbeReport newer = MakeProbe("r-1", 5, "tip");
  newer.mutable_position_m()->set_x(-42.0);
  newer.set_latency_us(999);
  store->AddProbes({newer});
  const auto probes = store->GetProbes("r-1");
  ASSERT_EQ(probes.size(), 1u);
  EXPECT_TRUE(Same(probes[0], newer));
}

}  // namespace
}  // namespace mbstream
