// Store: models round trip with their assets; PutModel is idempotent by id.
#include <gtest/gtest.h>

#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using testing::MakeBundle;
using testing::MakeModelInfo;
using testing::Same;
using testing::TempDirectory;

class StoreModelsTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreModelsTest);

TEST_P(StoreModelsTest, RoundTripWithAssets) {
  auto store = Open();
  const v1::ModelInfo info = MakeModelInfo("m-1", 1234);
  const v1::ModelBundle bundle = MakeBundle("arm", 3);
  EXPECT_TRUE(store->PutModel(info, bundle));
  const auto models = store->ListModels();
  ASSERT_EQ(models.size(), 1u);
  EXPECT_TRUE(Same(models[0], info));
  const auto loaded = store->GetModelBundle("m-1");
  ASSERT_TRUE(loaded.has_value());
  EXPECT_TRUE(Same(*loaded, bundle));
  EXPECT_EQ(loaded->assets(2).data(), bundle.assets(2).data());  // binary bytes intact
}

TEST_P(StoreModelsTest, UnknownModelHasNoBundle) {
  auto store = Open();
  EXPECT_FALSE(store->GetModelBundle("m-missing").has_value());
}

TEST_P(StoreModelsTest, PutModelIsIdempotentFirstCopyWins) {
  auto store = Open();
  const v1::ModelInfo first = MakeModelInfo("m-1", 100);
  v1::ModelInfo second = MakeModelInfo("m-1", 200);
  second.set_name("renamed");
  EXPECT_TRUE(store->PutModel(first, MakeBundle("first", 1)));
  EXPECT_FALSE(store->PutModel(second, MakeBundle("second", 4)));
  const auto models = store->ListModels();
  ASSERT_EQ(models.size(), 1u);
  EXPECT_TRUE(Same(models[0], first));
  const auto bundle = store->GetModelBundle("m-1");
  ASSERT_TRUE(bundle.has_value());
  EXPECT_EQ(bundle->name(), "first");
  EXPECT_EQ(bundle->assets_size(), 1);
}

TEST_P(StoreModelsTest, ListsOldestFirstAndFillsCreationTime) {
  auto store = Open();
  ASSERT_TRUE(store->PutModel(MakeModelInfo("m-late", 5000), MakeBundle("a", 0)));
  ASSERT_TRUE(store->PutModel(MakeModelInfo("m-early", 1000), MakeBundle("b", 0)));
  ASSERT_TRUE(store->PutModel(MakeModelInfo("m-now", 0), MakeBundle("c", 0)));
  const auto models = store->ListModels();
  ASSERT_EQ(models.size(), 3u);
  EXPECT_EQ(models[0].id(), "m-early");
  EXPECT_EQ(models[1].id(), "m-late");
  EXPECT_EQ(models[2].id(), "m-now");
  EXPECT_GT(models[2].created_unix_ms(), 1'600'000'000'000);  // stored as "now"
}

}  // namespace
}  // namespace mbstream
