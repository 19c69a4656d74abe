// GetStorage and BackupStorage through a real server, and what its free space does to health:
// the report counts what runs take; a disk below --min-free-mb turns the health service's
// new-runs status NOT_SERVING (the whole server stays SERVING) and shows in the report and in
// /metrics; a backup taken while a run writes starts a server on which every run is whole.
#include <gmock/gmock.h>

#include <atomic>

#include "grpc/health/v1/health.grpc.pb.h"
#include "server/app/health_status.h"
#include "server/runs/free_space_watch.h"
#include "tests/common/http_get.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;
using Health = grpc::health::v1::HealthCheckResponse;

v1::GetStorageResponse GetStorage(v1::Simulation::Stub& stub) {
  grpc::ClientContext context;
  v1::GetStorageResponse response;
  const grpc::Status status = stub.GetStorage(&context, v1::GetStorageRequest(), &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return response;
}

Health::ServingStatus CheckHealth(const std::string& address, const std::string& service) {
  auto stub = grpc::health::v1::Health::NewStub(
      grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  grpc::health::v1::HealthCheckRequest request;
  request.set_service(service);
  Health response;
  const grpc::Status status = stub->Check(&context, request, &response);
  return status.ok() ? response.status() : Health::UNKNOWN;
}

int64_t RunsIn(const v1::GetStorageResponse& storage, v1::RunState state) {
  for (const v1::StorageRunCount& count : storage.runs()) {
    if (count.state() == state) return count.runs();
  }
  return 0;
}

// The value of the unlabelled sample `name` in a /metrics answer, or -1.
double Sample(const std::string& text, const std::string& name) {
  const size_t at = text.find("\n" + name + " ");
  return at == std::string::npos ? -1 : std::stod(text.substr(at + name.size() + 2));
}

class StorageServiceTest : public ServerTest {};

TEST_F(StorageServiceTest, TheReportCountsWhatRunsTake) {
  StartServer();
  const v1::RunInfo run = StartRunOk("irb1600", SceneSpec("seed-run.json"));
  ASSERT_EQ(WaitForEnd(run.id()).state(), v1::FINISHED);

  const v1::GetStorageResponse storage = GetStorage(stub());
  EXPECT_EQ(storage.backend(), "sqlite");
  EXPECT_EQ(storage.location(), (data_.path() / "data").string());
  EXPECT_GT(storage.frame_bytes(), 0);
  EXPECT_GT(storage.run_bytes(), 0);
  EXPECT_GT(storage.disk_bytes(), storage.frame_bytes());
  EXPECT_GT(storage.free_bytes(), 0);
  EXPECT_EQ(storage.min_free_bytes(), int64_t{64} << 20);
  EXPECT_FALSE(storage.below_min_free());
  EXPECT_EQ(RunsIn(storage, v1::FINISHED), 1);
  ASSERT_GE(storage.models_size(), 1);
  EXPECT_EQ(storage.models(0).model_name(), "irb1600");  // most bytes first
  EXPECT_EQ(storage.models(0).runs(), 1);
  EXPECT_EQ(storage.models(0).frame_bytes(), storage.frame_bytes());
  EXPECT_EQ(storage.retain_runs(), 0);
  EXPECT_EQ(storage.retention_runs(), 0);
}

// The data directory's disk below --min-free-mb: new runs refused and said so before anyone
// asks (health), reads go on; back above it, all is as before.
TEST_F(StorageServiceTest, ADiskBelowTheMinimumIsNotServingForNewRuns) {
  TempDir data;
  std::atomic<int64_t> free_bytes{int64_t{1} << 30};
  ServerConfig config;
  config.listen = "127.0.0.1:0";
  config.data_dir = (data.path() / "data").string();
  config.models_dir = std::string(MBSTREAM_SOURCE_DIR) + "/models";
  config.metrics = "127.0.0.1:0";
  config.free_space_source = [&] { return std::optional<int64_t>(free_bytes.load()); };
  config.free_space_period_s = 3600.0;  // the test calls Check()
  std::unique_ptr<ServerHost> host = ServerHost::Start(config);
  auto stub = v1::Simulation::NewStub(
      grpc::CreateChannel(host->address(), grpc::InsecureChannelCredentials()));
  EXPECT_EQ(CheckHealth(host->address(), ""), Health::SERVING);
  EXPECT_EQ(CheckHealth(host->address(), kNewRunsHealthService), Health::SERVING);

  free_bytes = int64_t{3} << 20;
  EXPECT_FALSE(host->free_space()->Check());
  EXPECT_EQ(CheckHealth(host->address(), ""), Health::SERVING);  // reads and deletes go on
  EXPECT_EQ(CheckHealth(host->address(), kNewRunsHealthService), Health::NOT_SERVING);
  const v1::GetStorageResponse storage = GetStorage(*stub);
  EXPECT_TRUE(storage.below_min_free());
  EXPECT_EQ(storage.free_bytes(), int64_t{3} << 20);
  const std::string port = host->metrics_address().substr(host->metrics_address().rfind(':') + 1);
  const std::string metrics =
      HttpExchange(std::stoi(port), "GET /metrics HTTP/1.1\r\nHost: localhost\r\n\r\n");
  EXPECT_EQ(Sample(metrics, "mbstream_store_free_bytes"), 3 << 20);
  EXPECT_EQ(Sample(metrics, "mbstream_store_min_free_bytes"), 64 << 20);
  {
    grpc::ClientContext context;
    v1::StartRunRequest request;
    request.set_model("irb1600");
    *request.mutable_spec() = SceneSpec("seed-run.json");
    v1::RunInfo info;
    const grpc::Status status = stub->StartRun(&context, request, &info);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_THAT(status.error_message(), HasSubstr("mbstream delete"));
  }

  free_bytes = int64_t{1} << 30;  // space freed
  EXPECT_TRUE(host->free_space()->Check());
  EXPECT_EQ(CheckHealth(host->address(), kNewRunsHealthService), Health::SERVING);
  EXPECT_FALSE(GetStorage(*stub).below_min_free());
}

// A backup taken while a run writes its frames: a server started on it lists every run of the
// moment, the finished one whole and the running one INTERRUPTED with the frames stored until
// then, each result read back whole (the server checks each chunk's CRC-32C as it reads).
TEST_F(StorageServiceTest, ABackupTakenWhileARunWritesStartsAServerWithEveryRunWhole) {
  StartServer();
  const v1::RunInfo finished = StartRunOk("irb1600", SceneSpec("seed-run.json"));
  ASSERT_EQ(WaitForEnd(finished.id()).state(), v1::FINISHED);
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_duration_s(1000.0);
  spec.set_realtime(1.0);
  const v1::RunInfo running = StartRunOk("irb1600", spec);
  {  // until a chunk of it is stored (--frame-flush-s: 1 s of its clock)
    grpc::ClientContext context;
    v1::WatchRunRequest request;
    request.set_run_id(running.id());
    request.set_progress_interval_s(0.1);
    auto reader = stub().WatchRun(&context, request);
    v1::WatchEvent event;
    while (reader->Read(&event) && !(event.has_progress() && event.progress().t_s() > 1.5)) {
    }
    context.TryCancel();
    reader->Finish();
  }
  const std::string dir = (data_.path() / "backup").string();
  v1::BackupStorageResponse backup;
  {
    grpc::ClientContext context;
    v1::BackupStorageRequest request;
    request.set_dir(dir);
    const grpc::Status status = stub().BackupStorage(&context, request, &backup);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  EXPECT_EQ(backup.dir(), dir);
  EXPECT_EQ(backup.runs(), 2);
  EXPECT_GT(backup.frames_bytes(), 0);
  CancelRunOk(running.id());
  v1::RunInfo original;
  std::vector<v1::Frame> original_frames;
  ASSERT_TRUE(Result(finished.id(), &original, &original_frames, nullptr).ok());
  host_.reset();

  ServerConfig config;  // a server on the backup
  config.listen = "127.0.0.1:0";
  config.data_dir = dir;
  std::unique_ptr<ServerHost> restored = ServerHost::Start(config);
  stub_ = v1::Simulation::NewStub(
      grpc::CreateChannel(restored->address(), grpc::InsecureChannelCredentials()));
  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  ASSERT_TRUE(Result(finished.id(), &info, &frames, nullptr).ok());
  EXPECT_EQ(info.state(), v1::FINISHED);
  ASSERT_EQ(frames.size(), original_frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    ASSERT_EQ(frames[i].SerializeAsString(), original_frames[i].SerializeAsString()) << i;
  }
  frames.clear();
  ASSERT_TRUE(Result(running.id(), &info, &frames, nullptr).ok());
  EXPECT_EQ(info.state(), v1::INTERRUPTED);  // it was running when copied
  EXPECT_GT(frames.size(), 0u);
  EXPECT_EQ(static_cast<int64_t>(frames.size()), info.frames());
  for (size_t i = 0; i < frames.size(); ++i) ASSERT_EQ(frames[i].seq(), static_cast<int64_t>(i));
  stub_.reset();
  restored.reset();
}

}  // namespace
}  // namespace mbstream::testing
