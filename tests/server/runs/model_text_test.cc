// A model bundle's text fields must be UTF-8: anything else is refused at submit, naming the
// field and the line (found by start_run_fuzzer: such a bundle was stored and could not be
// read back, an internal error at the next StartRun).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include <unistd.h>

#include "server/runs/model_registry.h"
#include "server/runs/server_limits.h"
#include "server/store/store.h"
#include "shared/common/check.h"
#include "shared/common/utf8.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Optional;

TEST(Utf8Test, FindsTheFirstByteThatStartsNoCharacter) {
  EXPECT_EQ(FirstInvalidUtf8(""), std::nullopt);
  EXPECT_EQ(FirstInvalidUtf8("plain <robot/>"), std::nullopt);
  EXPECT_EQ(FirstInvalidUtf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\xA4\x96"),
            std::nullopt);                                          // é € 🤖
  EXPECT_THAT(FirstInvalidUtf8("caf\xE9"), Optional(3u));           // Latin-1 é
  EXPECT_THAT(FirstInvalidUtf8("a\xC3"), Optional(1u));             // cut short
  EXPECT_THAT(FirstInvalidUtf8("\xC0\xAF"), Optional(0u));          // overlong '/'
  EXPECT_THAT(FirstInvalidUtf8("x\xED\xA0\x80"), Optional(1u));     // a surrogate
  EXPECT_THAT(FirstInvalidUtf8("\xF4\x90\x80\x80"), Optional(0u));  // above U+10FFFF
  EXPECT_THAT(FirstInvalidUtf8("ok\x80"), Optional(2u));            // a lone continuation
}

TEST(ModelTextTest, ABundleThatIsNotUtf8IsRefusedNamingFieldAndLine) {
  const fs::path dir =
      fs::temp_directory_path() / ("mbstream-model-text-" + std::to_string(getpid()));
  fs::remove_all(dir);
  {
    ServerLimits limits;
    std::unique_ptr<Store> store = Store::Open(dir.string());
    ModelRegistry registry(store.get(), limits);
    v1::ModelBundle bundle;
    bundle.set_urdf("<robot name=\"r\">\n<!-- caf\xE9 -->\n<link name=\"base\"/>\n</robot>\n");
    try {
      registry.Submit(bundle, false);
      ADD_FAILURE() << "a Latin-1 URDF was accepted";
    } catch (const InputError& error) {
      EXPECT_THAT(error.what(), HasSubstr("bundle.urdf is not UTF-8 text: line 2"));
      EXPECT_THAT(error.what(), HasSubstr("send UTF-8 text"));
    }
    bundle.set_urdf("<robot name=\"r\">\n<link name=\"base\"/>\n</robot>\n");
    bundle.set_name("r\xFF");
    EXPECT_THROW(registry.Submit(bundle, false), InputError);
    EXPECT_EQ(store->ListModels().size(), 0u);  // nothing half-written
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream
