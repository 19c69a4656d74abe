// Ctrl-C means stop, even mid-parse (issue 42, item 6): a model of 100,000 XML elements being
// imported is abandoned at its next check when its call is cancelled or the server stops
// (import_cancel.h); mbstream-server, stopped by SIGINT while it imports one, exits within
// 1 s with its store clean (the model absent, the store opening without complaint).
#include "server/parse/import_cancel.h"

#include <gmock/gmock.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include "server/parse/urdf_import.h"
#include "server/service/status_from_exception.h"
#include "tests/common/sanitized_build.h"
#include "tests/common/server_process.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// A chain of `links` links (about 10 elements a link and its joint).
std::string ChainUrdf(int links) {
  std::string text = "<robot name=\"abandoned_chain\">\n";
  const std::string inertial =
      "<inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" "
      "ixz=\"0\" iyz=\"0\"/></inertial>";
  for (int i = 0; i < links; ++i) {
    text += "<link name=\"l" + std::to_string(i) + "\">" + inertial + "</link>\n";
  }
  for (int i = 1; i < links; ++i) {
    text += "<joint name=\"j" + std::to_string(i) + "\" type=\"revolute\"><parent link=\"l" +
            std::to_string(i - 1) + "\"/><child link=\"l" + std::to_string(i) +
            "\"/><origin xyz=\"0 0 0.001\"/><axis xyz=\"0 1 0\"/><limit lower=\"-3\" "
            "upper=\"3\" effort=\"100\" velocity=\"5\"/></joint>\n";
  }
  return text + "</robot>\n";
}

constexpr int kLinks = 10'000;  // 100,000 elements

TEST(ImportCancelTest, AnImportWhoseCallIsCancelledIsAbandonedAtItsNextCheck) {
  const std::string urdf = ChainUrdf(kLinks);
  int checks = 0;
  {
    // The call is cancelled once the import is under way (its third check).
    const ImportCancelScope scope([&] { return ++checks >= 3; });
    try {
      ImportUrdf(urdf, "chain.urdf", {}, {});
      ADD_FAILURE() << "imported; expected ImportCancelled";
    } catch (const ImportCancelled& cancelled) {
      EXPECT_THAT(cancelled.what(), HasSubstr("the call was cancelled"));
      // The service answers it UNAVAILABLE, like any call to a server that is stopping.
      EXPECT_EQ(StatusFromException(std::current_exception()).error_code(),
                grpc::StatusCode::UNAVAILABLE);
    }
  }
  EXPECT_EQ(checks, 3);
  // Without a scope nothing cancels it.
  EXPECT_EQ(ImportUrdf(urdf, "chain.urdf", {}, {}).model.num_dofs(), kLinks - 1);
}

TEST(ImportCancelTest, TheServersStopCancelsEveryImport) {
  const std::string urdf = ChainUrdf(kLinks);
  CancelAllImports();
  try {
    ImportUrdf(urdf, "chain.urdf", {}, {});
    ADD_FAILURE() << "imported; expected ImportCancelled";
  } catch (const ImportCancelled& cancelled) {
    EXPECT_THAT(cancelled.what(), HasSubstr("the server is stopping"));
  }
  ResetImportCancelForTest();
  EXPECT_NO_THROW(ImportUrdf(urdf, "chain.urdf", {}, {}));
}

// The server with the import under way (its log says so): SIGINT, and it is gone within 1 s
// (10 s in a sanitizer's build), exit status 0; the submit is told; restarted on the same data,
// the store opens and holds no trace of the model.
TEST(ImportCancelTest, SigintMidImportStopsTheServerWithinASecondWithTheStoreClean) {
  const fs::path dir = fs::temp_directory_path() /
                       ("mbstream-import-cancel-" + std::to_string(std::random_device()()));
  fs::create_directories(dir);
  std::ofstream(dir / "chain.urdf") << ChainUrdf(kLinks);
  const std::vector<std::string> flags = {"--max-links", "20000", "--log-level", "debug"};
  auto server =
      std::make_unique<testing::ServerProcess>(MBSTREAM_SERVER, (dir / "data").string(), flags);
  const std::string submit = std::string(MBSTREAM_CLI) + " --server " + server->address() +
                             " submit " + (dir / "chain.urdf").string() + " > " +
                             (dir / "submit.out").string() + " 2>&1; echo \"exit $?\" >> " +
                             (dir / "submit.out").string();
  std::thread client([&] { testing::RunCommand(submit); });
  ASSERT_TRUE(testing::WaitForLineIn(server->log_path(), "SubmitModel: importing", 60))
      << testing::ReadTextFile(server->log_path());
  const auto signalled = std::chrono::steady_clock::now();
  const int status = server->Stop();
  const double stop_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  client.join();
  std::printf("SIGINT mid-import of %d links: the server exited in %.3f s\n", kLinks, stop_s);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_LT(stop_s, testing::kSanitizedBuild ? 10.0 : 1.0);
  const std::string log = testing::ReadTextFile(server->log_path());
  const std::string said = testing::ReadTextFile((dir / "submit.out").string());
  // The import was abandoned (or, on a fast machine, had just finished: then it is stored).
  const bool abandoned = said.find("the server is stopping") != std::string::npos;
  EXPECT_TRUE(abandoned || said.find("exit 0") != std::string::npos) << said;
  server =
      std::make_unique<testing::ServerProcess>(MBSTREAM_SERVER, (dir / "data").string(), flags);
  const testing::CommandOutcome models =
      testing::RunCommand(std::string(MBSTREAM_CLI) + " --server " + server->address() + " models");
  EXPECT_EQ(models.exit_code, 0) << models.output;
  if (abandoned) {
    EXPECT_THAT(models.output, ::testing::Not(HasSubstr("abandoned_chain"))) << models.output;
  }
  server.reset();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream
