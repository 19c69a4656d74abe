#include "tests/server/service/server_fixture.h"

#include <chrono>
#include <random>
#include <thread>

#include "server/runs/run_manager.h"
#include "server/spec/run_spec_json.h"
#include "server/wire/model_bundle_files.h"
#include "server/wire/stats_conversion.h"

namespace mbstream::testing {

namespace fs = std::filesystem;

TempDir::TempDir() {
  std::random_device random;
  path_ = fs::temp_directory_path() /
          ("mbstream-test-" + std::to_string(random()) + "-" + std::to_string(random()));
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code error;
  fs::remove_all(path_, error);
}

void ServerTest::StartServer(const ServerLimits& limits, const std::string& token_file) {
  stub_.reset();
  host_.reset();  // a test may restart the server on the same data directory
  ServerConfig config;
  config.listen = "127.0.0.1:0";
  config.data_dir = (data_.path() / "data").string();
  config.models_dir = std::string(MBSTREAM_SOURCE_DIR) + "/models";
  config.limits = limits;
  config.token_file = token_file;
  host_ = ServerHost::Start(config);
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(256 << 20);
  stub_ = v1::Simulation::NewStub(
      grpc::CreateCustomChannel(host_->address(), grpc::InsecureChannelCredentials(), arguments));
}

void ServerTest::TearDown() {
  stub_.reset();
  host_.reset();
}

grpc::Status ServerTest::Submit(const v1::ModelBundle& bundle, v1::ModelInfo* info) {
  grpc::ClientContext context;
  v1::SubmitModelRequest request;
  *request.mutable_bundle() = bundle;
  return stub_->SubmitModel(&context, request, info);
}

v1::ModelInfo ServerTest::SubmitOk(const v1::ModelBundle& bundle) {
  v1::ModelInfo info;
  const grpc::Status status = Submit(bundle, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return info;
}

grpc::Status ServerTest::StartRun(const std::string& model, const v1::RunSpec& spec,
                                  v1::RunInfo* info) {
  grpc::ClientContext context;
  v1::StartRunRequest request;
  request.set_model(model);
  *request.mutable_spec() = spec;
  return stub_->StartRun(&context, request, info);
}

v1::RunInfo ServerTest::StartRunOk(const std::string& model, const v1::RunSpec& spec) {
  v1::RunInfo info;
  const grpc::Status status = StartRun(model, spec, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return info;
}

v1::RunInfo ServerTest::CancelRunOk(const std::string& run_id) {
  grpc::ClientContext context;
  v1::CancelRunRequest request;
  request.set_run_id(run_id);
  v1::RunInfo info;
  const grpc::Status status = stub_->CancelRun(&context, request, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return info;
}

v1::RunInfo ServerTest::WaitForEnd(const std::string& run_id) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  v1::WatchRunRequest request;
  request.set_run_id(run_id);
  request.set_progress_interval_s(60.0);  // a change of state is sent at once
  auto reader = stub_->WatchRun(&context, request);
  v1::WatchEvent event;
  v1::RunInfo info;
  while (reader->Read(&event)) {
    if (event.has_progress()) info = event.progress();
  }
  const grpc::Status status = reader->Finish();
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_TRUE(IsFinalState(info.state())) << "run " << run_id << " did not end within 60 s";
  return info;
}

grpc::Status ServerTest::Result(const std::string& run_id, v1::RunInfo* info,
                                std::vector<v1::Frame>* frames,
                                std::vector<v1::ProbeReport>* probes, bool wait,
                                std::chrono::milliseconds deadline) {
  grpc::ClientContext context;
  if (deadline.count() > 0) context.set_deadline(std::chrono::system_clock::now() + deadline);
  v1::GetResultRequest request;
  request.set_run_id(run_id);
  request.set_wait(wait);
  auto reader = stub_->GetResult(&context, request);
  v1::ResultChunk chunk;
  while (reader->Read(&chunk)) {
    if (chunk.has_info()) *info = chunk.info();
    frames->insert(frames->end(), chunk.frames().begin(), chunk.frames().end());
    if (probes) probes->insert(probes->end(), chunk.probes().begin(), chunk.probes().end());
  }
  return reader->Finish();
}

v1::RunSpec ServerTest::SceneSpec(const std::string& file) {
  return LoadRunSpecFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/irb1600/" + file);
}

v1::ModelBundle ServerTest::IrbBundle() {
  return ReadModelBundle(std::string(MBSTREAM_SOURCE_DIR) + "/models/irb1600/irb1600.urdf", "", {},
                         "");
}

void ServerTest::WaitForSubscribers(int count) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (host().runs().subscriptions().count() != count &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(host().runs().subscriptions().count(), count);
}

}  // namespace mbstream::testing
