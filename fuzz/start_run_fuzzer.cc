// Fuzzes a whole SubmitModel + StartRun request through the server's own classes (no gRPC):
// ModelRegistry::Submit compiles the bundle, RunManager::Start validates the spec against
// the model and the limits, and an accepted run executes on a worker to its end. Every
// outcome must be a RunInfo or an InputError / RequestError with a message; a run must end
// (within 60 s; the limits below keep accepted runs tiny) and never with an internal error.
//
// Input (fuzz/README.md): the URDF or SDFormat text, then a line "@@spec", then the RunSpec
// JSON, then optionally a line "@@assets" and one asset name per line (each sent with a small
// body).
#include <spdlog/spdlog.h>

#include <unistd.h>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <memory>
#include <string>

#include "server/runs/model_registry.h"
#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/spec/run_spec_json.h"
#include "server/store/store.h"
#include "shared/common/check.h"

namespace {

namespace fs = std::filesystem;
using namespace mbstream;  // NOLINT

struct Request {
  v1::ModelBundle bundle;
  std::string spec_json;
};

// Splits the input at the first "\n@@spec\n" and "\n@@assets\n".
Request Split(const std::string& input) {
  Request request;
  std::string urdf = input;
  std::string assets;
  if (size_t at = urdf.find("\n@@spec\n"); at != std::string::npos) {
    request.spec_json = urdf.substr(at + 8);
    urdf.resize(at);
  }
  if (size_t at = request.spec_json.find("\n@@assets\n"); at != std::string::npos) {
    assets = request.spec_json.substr(at + 10);
    request.spec_json.resize(at);
  }
  request.bundle.set_urdf(urdf);
  request.bundle.set_urdf_file_name("fuzz.urdf");
  size_t begin = 0;
  while (begin < assets.size()) {
    size_t end = assets.find('\n', begin);
    if (end == std::string::npos) end = assets.size();
    v1::Asset* asset = request.bundle.add_assets();
    asset->set_name(assets.substr(begin, end - begin));
    asset->set_data("solid fuzz\nendsolid fuzz\n");
    begin = end + 1;
  }
  return request;
}

// One server (store, registry, run manager) in a temporary directory, replaced every
// kIterationsPerServer inputs so that stored models and runs do not pile up.
class Server {
 public:
  Server() {
    const fs::path base = fs::exists("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    dir_ = base / ("mbstream-fuzz-" + std::to_string(getpid()));
    fs::remove_all(dir_);
    limits_.workers = 1;
    limits_.max_duration_s = 0.2;  // accepted runs stay tiny: the fuzzer tests validation
    limits_.max_output_frames = 200;
    limits_.max_internal_steps = 20'000;
    // A CPU cap as well: 20,000 steps of a 100-joint model take over a minute under ASan
    // (models/big/chain100.urdf with seed-run.json did, and timed libFuzzer out).
    limits_.max_run_cpu_s = 2.0;
    limits_.max_model_bytes = 1 << 20;
    limits_.probe_grace_s = 0.0;
    limits_.max_models = 1 << 20;  // the server is replaced before the store grows large
    store_ = Store::Open(dir_.string());
    models_ = std::make_unique<ModelRegistry>(store_.get(), limits_);
    runs_ = std::make_unique<RunManager>(models_.get(), store_.get(), limits_);
  }
  ~Server() {
    runs_.reset();
    models_.reset();
    store_.reset();
    fs::remove_all(dir_);
  }
  ModelRegistry& models() { return *models_; }
  RunManager& runs() { return *runs_; }

 private:
  fs::path dir_;
  ServerLimits limits_;
  std::unique_ptr<Store> store_;
  std::unique_ptr<ModelRegistry> models_;
  std::unique_ptr<RunManager> runs_;
};

constexpr int kIterationsPerServer = 2000;

void Fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "start_run_fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

// Waits for the run's end; returns its final info.
v1::RunInfo WaitForEnd(RunManager& runs, const std::string& run_id) {
  std::shared_ptr<Subscription> subscription = runs.subscriptions().SubscribeRun(run_id, false);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  bool ended = false;
  while (!ended) {
    if (std::chrono::steady_clock::now() > deadline) Fail("run did not end in 60 s", run_id);
    std::deque<StreamEvent> events;
    int64_t missed = 0;
    if (!subscription->Pop(std::chrono::milliseconds(100), 64, &events, &missed) &&
        events.empty()) {
      break;  // closed
    }
    for (const StreamEvent& event : events) {
      if (event.kind == StreamEvent::Kind::kRunEnded) ended = true;
    }
  }
  runs.subscriptions().Unsubscribe(subscription);
  return runs.Get(run_id);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // spdlog's registry first, so that it outlives the server at exit (statics end in reverse
  // order): the run manager's shutdown logs. Without it the exit crashed on spdlog's
  // destroyed sinks in one exit of two (the seed replay of the Release tree, 2026-12-02).
  static const std::shared_ptr<spdlog::logger> logger = spdlog::default_logger();
  static std::unique_ptr<Server> server;
  static int iterations = 0;
  if (!server || ++iterations % kIterationsPerServer == 0) {
    server.reset();
    server = std::make_unique<Server>();
  }
  const Request request = Split(std::string(reinterpret_cast<const char*>(data), size));
  std::string model_id;
  try {
    model_id = server->models().Submit(request.bundle, false).id();
  } catch (const InputError& error) {
    if (std::string(error.what()).empty()) Fail("empty InputError", "Submit");
    return 0;
  } catch (const RequestError& error) {
    if (std::string(error.what()).empty()) Fail("empty RequestError", "Submit");
    return 0;
  }
  v1::RunInfo info;
  try {
    info = server->runs().Start(model_id, ParseRunSpecJson(request.spec_json, "spec.json"));
  } catch (const InputError& error) {
    if (std::string(error.what()).empty()) Fail("empty InputError", "Start");
    return 0;
  } catch (const RequestError& error) {
    if (std::string(error.what()).empty()) Fail("empty RequestError", "Start");
    return 0;
  }
  if (info.expected_frames() < 0) Fail("negative expected_frames", info.id());
  const v1::RunInfo final_info = WaitForEnd(server->runs(), info.id());
  if (final_info.message().rfind("internal error", 0) == 0) {
    Fail("run ended with an internal error", final_info.message());
  }
  return 0;
}
