// The cost of the cluster's Subscribe proxy (docs/cluster.md, "Calls for runs on other
// replicas"): two replicas on a PostgreSQL started here (as cluster_e2e_test does), one kept
// busy so that the other integrates every run; each run is subscribed either directly on its
// owner or through the other replica. Prints, per way, the frames delivered per second of
// wall time (subscribed .. run_ended) and the frames dropped for a slow consumer, and their
// medians over the runs.
//
//   cluster_proxy_bench [RUNS=5] [DURATION_S=20] [OUTPUT_INTERVAL_S=0.001]
#include <grpcpp/grpcpp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "tests/common/postgres_cluster.h"
#include "tests/common/server_process.h"

namespace {

using mbstream::testing::PostgresCluster;
using mbstream::testing::ServerProcess;
namespace v1 = mbstream::v1;
using Clock = std::chrono::steady_clock;

struct Replica {
  Replica(const std::string& dir, const std::string& uri)
      : process(MBSTREAM_SERVER, dir, {"--store", uri, "--workers", "1"}),
        stub(v1::Simulation::NewStub(
            grpc::CreateChannel(process.address(), grpc::InsecureChannelCredentials()))) {}
  std::string Start(double duration_s, double interval_s, double realtime) {
    grpc::ClientContext context;
    v1::StartRunRequest request;
    request.set_model("single_pendulum");
    request.mutable_spec()->set_duration_s(duration_s);
    request.mutable_spec()->set_output_interval_s(interval_s);
    request.mutable_spec()->set_realtime(realtime);
    v1::RunInfo info;
    if (!stub->StartRun(&context, request, &info).ok()) std::abort();
    return info.id();
  }
  ServerProcess process;
  std::unique_ptr<v1::Simulation::Stub> stub;
};

struct Rate {
  double frames_per_s = 0;
  int64_t frames = 0, missed = 0;
};

Rate Subscribe(const std::string& address, const std::string& run_id) {
  auto stub =
      v1::Simulation::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  auto stream = stub->Subscribe(&context);
  v1::SubscribeRequest start;
  start.mutable_start()->set_run_id(run_id);
  stream->Write(start);
  v1::SubscribeEvent event;
  Rate rate;
  Clock::time_point first;
  while (stream->Read(&event)) {
    if (event.has_frames()) {
      if (rate.frames == 0) first = Clock::now();
      rate.frames += event.frames().frames_size();
      rate.missed += event.frames().missed();
    }
    if (event.has_run_ended()) break;
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - first).count();
  stream->WritesDone();
  while (stream->Read(&event)) {
  }
  const grpc::Status status = stream->Finish();
  if (!status.ok() || rate.frames == 0) {
    std::printf("run %s: %d %s\n", run_id.c_str(), static_cast<int>(status.error_code()),
                status.error_message().c_str());
  }
  rate.frames_per_s = seconds > 0 ? static_cast<double>(rate.frames) / seconds : 0;
  return rate;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::atoi(argv[1]) : 5;
  const double duration = argc > 2 ? std::atof(argv[2]) : 20.0;
  const double interval = argc > 3 ? std::atof(argv[3]) : 0.001;
  if (const std::string why = PostgresCluster::Unavailable(); !why.empty()) {
    std::printf("cluster_proxy_bench: no PostgreSQL: %s\n", why.c_str());
    return 77;
  }
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("mbstream-proxy-bench-" + std::to_string(std::random_device()()));
  std::filesystem::create_directories(dir);
  {
    PostgresCluster cluster;
    const std::string uri = cluster.CreateDatabase("mbstream");
    Replica busy((dir / "busy").string(), uri);
    // Its only worker kept busy (waited for): the other replica claims every later run.
    const std::string blocker = busy.Start(3600.0, 1.0, 1.0);
    for (v1::RunInfo info; info.state() != v1::RUNNING;) {
      grpc::ClientContext context;
      v1::GetRunRequest request;
      request.set_run_id(blocker);
      busy.stub->GetRun(&context, request, &info);
    }
    Replica owner((dir / "owner").string(), uri);
    std::vector<double> direct, proxied;
    for (int i = 0; i < runs; ++i) {
      for (bool through_proxy : {false, true}) {
        const std::string run = owner.Start(duration, interval, 0.0);
        const Rate rate =
            Subscribe(through_proxy ? busy.process.address() : owner.process.address(), run);
        (through_proxy ? proxied : direct).push_back(rate.frames_per_s);
        std::printf("run %d %-8s %8lld frames delivered, %8lld dropped, %10.0f frames/s\n", i,
                    through_proxy ? "proxied" : "direct", static_cast<long long>(rate.frames),
                    static_cast<long long>(rate.missed), rate.frames_per_s);
      }
    }
    std::printf("median frames/s: direct %.0f, proxied %.0f (%.1f%%)\n", Median(direct),
                Median(proxied), 100.0 * (Median(proxied) / Median(direct) - 1.0));
  }
  std::filesystem::remove_all(dir);
  return 0;
}
