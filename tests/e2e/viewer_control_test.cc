// The viewer's control service (--listen): status, snapshot and LoadScene on a real
// offscreen viewer that follows a real server.
#include <gmock/gmock.h>
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "mbstream/v1/viewer_service.grpc.pb.h"
#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::string ReadFile(const fs::path& path) { return ReadTextFile(path.string()); }

// The rest of the line with `marker` in `log`, failing the test after 30 s without it.
std::string WaitForLine(const fs::path& log, const std::string& marker) {
  const std::optional<std::string> rest = WaitForLineIn(log.string(), marker);
  if (!rest) ADD_FAILURE() << "no '" << marker << "' in " << log << ":\n" << ReadFile(log);
  return rest.value_or("");
}

TEST(ViewerControlTest, StatusSnapshotAndLoadScene) {
  const fs::path dir =
      fs::temp_directory_path() / ("mbstream-control-" + std::to_string(std::random_device()()));
  fs::create_directories(dir);
  ServerProcess server(MBSTREAM_SERVER, (dir / "data").string());
  const fs::path log = dir / "viewer.log";
  ASSERT_EQ(RunCommand("scripts/with-xvfb.sh " + std::string(MBSTREAM_VIEWER) + " --server " +
                       server.address() + " --follow --exit-after-runs 1 --offscreen --size " +
                       "320x240 --listen 127.0.0.1:0 > " + log.string() + " 2>&1 &")
                .exit_code,
            0);
  const std::string control = WaitForLine(log, "control service listening on ");
  WaitForLine(log, "subscribed to");
  auto viewer =
      v1::Viewer::NewStub(grpc::CreateChannel(control, grpc::InsecureChannelCredentials()));

  v1::ViewerStatus status;
  {
    grpc::ClientContext context;
    ASSERT_TRUE(viewer->GetStatus(&context, v1::ViewerStatusRequest(), &status).ok());
    EXPECT_EQ(status.server(), server.address());
    EXPECT_EQ(status.state(), "waiting");
  }
  {
    grpc::ClientContext context;
    v1::SnapshotResponse png;
    EXPECT_EQ(viewer->Snapshot(&context, v1::SnapshotRequest(), &png).error_code(),
              grpc::StatusCode::FAILED_PRECONDITION);
  }
  {
    grpc::ClientContext context;
    v1::LoadSceneRequest request;
    request.set_scene_script("Cylinder c (radius 10 height\n");
    const grpc::Status loaded = viewer->LoadScene(&context, request, &status);
    EXPECT_EQ(loaded.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_THAT(loaded.error_message(), HasSubstr(":1:"));
  }
  {
    grpc::ClientContext context;
    v1::LoadSceneRequest request;
    request.set_scene_script(ReadFile("models/irb1600/irb1600.scene"));
    const grpc::Status loaded = viewer->LoadScene(&context, request, &status);
    ASSERT_TRUE(loaded.ok()) << loaded.error_message();
  }
  {
    grpc::ClientContext context;
    v1::SnapshotResponse png;
    ASSERT_TRUE(viewer->Snapshot(&context, v1::SnapshotRequest(), &png).ok());
    EXPECT_EQ(png.width(), 320);
    EXPECT_EQ(png.height(), 240);
    EXPECT_EQ(png.png().substr(1, 3), "PNG");
  }
  // A run: the viewer shows it, then exits (--exit-after-runs 1).
  const CommandOutcome run =
      RunCommand(std::string(MBSTREAM_CLI) + " --server " + server.address() +
                 " run irb1600 --spec models/irb1600/seed-run.json --realtime 20 --watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(WaitForLine(log, "viewer done: "), HasSubstr("401 probe reports"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream::testing
