// Built-in models are read and compiled when first asked for, not at start (the server
// listens at once): by name only that one, by a listing or a submit all of them, each once
// even when several threads ask together; a restart finds them in the store.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "server/runs/model_registry.h"
#include "server/runs/request_error.h"
#include "server/store/store.h"
#include "server/wire/model_bundle_files.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;

class BuiltinModelsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream-builtins-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    Open();
  }
  void TearDown() override {
    models_.reset();
    store_.reset();
    fs::remove_all(dir_);
  }
  void Open() {
    models_.reset();
    store_.reset();
    store_ = Store::Open(dir_.string());
    models_ = std::make_unique<ModelRegistry>(store_.get(), ServerLimits());
    models_->LoadStored();
    builtins_ = models_->LoadBuiltins(std::string(MBSTREAM_SOURCE_DIR) + "/models");
  }
  int StoredModels() const { return static_cast<int>(store_->ListModels().size()); }

  fs::path dir_;
  std::unique_ptr<Store> store_;
  std::unique_ptr<ModelRegistry> models_;
  int builtins_ = 0;
};

TEST_F(BuiltinModelsTest, NothingIsCompiledAtStartAndANameCompilesOnlyItsModel) {
  ASSERT_GE(builtins_, 5);  // irb1600, the pendulums, the linkages, the big chains
  EXPECT_EQ(models_->compiled_count(), 0);
  EXPECT_EQ(StoredModels(), 0);

  EXPECT_EQ(models_->Find("irb1600")->info.name(), "irb1600");
  EXPECT_EQ(models_->compiled_count(), 1);
  EXPECT_EQ(StoredModels(), 1);
  EXPECT_TRUE(models_->Info("irb1600").builtin());
  EXPECT_EQ(StoredModels(), 1);

  EXPECT_EQ(static_cast<int>(models_->List().size()), builtins_);  // a listing reads them all
  EXPECT_EQ(StoredModels(), builtins_);
}

TEST_F(BuiltinModelsTest, AnUnknownNameListsEveryBuiltInModel) {
  try {
    models_->Find("irb16000");
    FAIL() << "found a model that does not exist";
  } catch (const RequestError& error) {
    EXPECT_EQ(error.kind(), RequestErrorKind::kNotFound);
    EXPECT_NE(std::string(error.what()).find("irb1600 ("), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("four_bar ("), std::string::npos) << error.what();
  }
}

TEST_F(BuiltinModelsTest, ABuiltInModelSubmittedAgainIsThatModel) {
  // As scripts/demo.sh does: `mbstream submit models/irb1600`, before anything asked for it.
  const v1::ModelInfo submitted = models_->Submit(
      ReadModelBundle(std::string(MBSTREAM_SOURCE_DIR) + "/models/irb1600", "", {}, ""), false);
  EXPECT_TRUE(submitted.builtin());
  EXPECT_EQ(submitted.id(), models_->Info("irb1600").id());
  EXPECT_EQ(StoredModels(), builtins_);
}

TEST_F(BuiltinModelsTest, ARestartFindsThemInTheStoreAndCompilesNone) {
  const v1::ModelInfo by_name = models_->Info("single_pendulum");
  EXPECT_EQ(models_->List().size(), static_cast<std::size_t>(builtins_));
  Open();  // a restart: every built-in is in the store, none compiled
  EXPECT_EQ(models_->compiled_count(), 0);
  EXPECT_EQ(models_->Info("single_pendulum").id(), by_name.id());
  EXPECT_EQ(static_cast<int>(models_->List().size()), builtins_);
  EXPECT_EQ(models_->compiled_count(), 0);  // known by content: listed, not compiled
}

TEST_F(BuiltinModelsTest, ThreadsAskingTogetherCompileEachModelOnce) {
  std::vector<std::thread> threads;
  std::vector<std::string> ids(4);
  for (int i = 0; i < 4; ++i) {
    threads.emplace_back([&, i] {
      ids[i] = i % 2 == 0 ? models_->Find("four_bar")->info.id() : models_->List().at(0).id();
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(ids[0], ids[2]);
  EXPECT_EQ(static_cast<int>(models_->List().size()), builtins_);
  EXPECT_EQ(StoredModels(), builtins_);
}

}  // namespace
}  // namespace mbstream
