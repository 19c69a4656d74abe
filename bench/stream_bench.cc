// Streaming through the real server over loopback TCP, against a bare gRPC baseline.
//
//   BM_StreamFrames          frames/s from an as-fast-as-possible run to one subscriber
//   BM_BareStreamFrames      frames/s of a bare server stream of the same Frame messages
//   BM_ProbeRoundTrip        frame out of the server -> probe back (p50_us, p99_us)
//   BM_BarePingPong/0, /10   a bare bidi echo of one Frame, hot or paced every 10 ms
//   BM_BarePingPongBesideServer  the hot echo with the mbstream server running in the process
//   BM_ControlRoundTrip      a 1 kHz controller on the IRB 1600 over Simulation.Control for
//                            10 s of simulated time: command out -> next state back (p50_us,
//                            p99_us) and the run's rate (x_real_time)
//   BM_ControlRoundTripOutOfProcess, BM_BarePingPongOutOfProcess  the same round trip and the
//                            hot echo with the server in another process, as a user's
//                            controller has it (bench/control_process.sh starts the servers
//                            and gives their addresses in MBSTREAM_BENCH_SERVER and
//                            MBSTREAM_BENCH_ECHO; `stream_bench --serve-echo` is the echo)
//   BM_ReplayFrames/V/P      frames/s of an unpaced replay of a stored run to V viewers at
//                            once, each answering every frame with P probes (issue 17)
//   BM_ReplayFirstFrame/S    a 1,000,001-frame stored run: Subscribe -> first replayed frame,
//                            from frame S
#include <benchmark/benchmark.h>
#include <grpcpp/grpcpp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>
#include <thread>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/app/server_host.h"
#include "server/runs/replay_cursor.h"
#include "server/runs/run_manager.h"
#include "server/spec/run_spec_json.h"
#include "stream_baseline.grpc.pb.h"

namespace mbstream {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

// One server for the whole program, on a fresh data directory.
struct BenchServer {
  BenchServer() {
    data = fs::temp_directory_path() / ("mbstream-bench-" + std::to_string(getpid()));
    ServerConfig config;
    config.listen = "127.0.0.1:0";
    config.data_dir = data.string();
    config.models_dir = std::string(MBSTREAM_SOURCE_DIR) + "/models";
    host = ServerHost::Start(config);
    grpc::ChannelArguments arguments;
    arguments.SetMaxReceiveMessageSize(256 << 20);
    stub = v1::Simulation::NewStub(
        grpc::CreateCustomChannel(host->address(), grpc::InsecureChannelCredentials(), arguments));
  }
  ~BenchServer() {
    stub.reset();
    host.reset();
    fs::remove_all(data);
  }
  fs::path data;
  std::unique_ptr<ServerHost> host;
  std::unique_ptr<v1::Simulation::Stub> stub;
};

BenchServer& Server() {
  static BenchServer server;
  return server;
}

v1::RunSpec SeedSpec() {
  return LoadRunSpecFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/irb1600/seed-run.json");
}

using Stream = grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>;

std::unique_ptr<Stream> Follow(grpc::ClientContext* context, int max_batch) {
  std::unique_ptr<Stream> stream = Server().stub->Subscribe(context);
  v1::SubscribeRequest start;
  start.mutable_start()->set_follow(true);
  start.mutable_start()->set_max_batch(max_batch);
  stream->Write(start);
  while (Server().host->runs().subscriptions().count() == 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return stream;
}

std::string StartRun(const v1::RunSpec& spec) {
  grpc::ClientContext context;
  v1::StartRunRequest request;
  request.set_model("irb1600");
  *request.mutable_spec() = spec;
  v1::RunInfo info;
  const grpc::Status status = Server().stub->StartRun(&context, request, &info);
  if (!status.ok()) throw std::runtime_error(status.error_message());
  return info.id();
}

void Percentiles(benchmark::State& state, std::vector<double> us) {
  if (us.empty()) return;
  std::sort(us.begin(), us.end());
  state.counters["p50_us"] = us[us.size() / 2];
  state.counters["p99_us"] = us[std::min(us.size() - 1, us.size() * 99 / 100)];
  state.counters["samples"] = static_cast<double>(us.size());
}

// A run of 100,001 frames (seed kinematics, output every 0.2 ms) as fast as possible, read
// by one subscriber; range(0) = most frames per message.
void BM_StreamFrames(benchmark::State& state) {
  v1::RunSpec spec = SeedSpec();
  spec.set_output_interval_s(2e-4);
  int64_t received = 0, missed = 0;
  for (auto _ : state) {
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = Follow(&context, static_cast<int>(state.range(0)));
    StartRun(spec);
    v1::SubscribeEvent event;
    // Timed: run started -> last frame received (not the run's wait for probes after it).
    Clock::time_point first{}, last{};
    while (stream->Read(&event) && !event.has_run_ended()) {
      if (event.has_run_started()) first = Clock::now();
      if (event.has_frames()) last = Clock::now();
      received += event.frames().frames_size();
      missed += event.frames().missed();
    }
    state.SetIterationTime(std::chrono::duration<double>(last - first).count());
    context.TryCancel();
    stream->Finish();
    while (Server().host->runs().subscriptions().count() != 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  state.SetItemsProcessed(received);
  state.counters["missed"] = static_cast<double>(missed);
}
BENCHMARK(BM_StreamFrames)
    ->Arg(1)
    ->Arg(256)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

// The viewer side: answer each frame with a probe at once; latencies as stored by the
// server (frame written -> probe read). 401 frames paced at 100 frames/s of wall time.
void BM_ProbeRoundTrip(benchmark::State& state) {
  v1::RunSpec spec = SeedSpec();
  spec.set_duration_s(4.0);
  spec.set_output_interval_s(0.01);
  spec.set_realtime(1.0);
  std::vector<double> latencies;
  for (auto _ : state) {
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = Follow(&context, 1);
    const std::string run_id = StartRun(spec);
    v1::SubscribeEvent event;
    v1::SubscribeRequest reply;
    while (stream->Read(&event) && !event.has_run_ended()) {
      for (const v1::Frame& frame : event.frames().frames()) {
        v1::ProbeReport* probe = reply.mutable_probe();
        probe->set_run_id(run_id);
        probe->set_seq(frame.seq());
        probe->set_t_s(frame.t_s());
        probe->set_probe("tcp");
        *probe->mutable_position_m() = frame.tcp_m();
        stream->Write(reply);
      }
    }
    context.TryCancel();
    stream->Finish();
    state.PauseTiming();
    grpc::ClientContext result_context;
    v1::GetResultRequest request;
    request.set_run_id(run_id);
    auto reader = Server().stub->GetResult(&result_context, request);
    v1::ResultChunk chunk;
    while (reader->Read(&chunk)) {
      for (const v1::ProbeReport& p : chunk.probes()) {
        if (p.latency_us() >= 0) latencies.push_back(static_cast<double>(p.latency_us()));
      }
    }
    reader->Finish();
    while (Server().host->runs().subscriptions().count() != 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    state.ResumeTiming();
  }
  Percentiles(state, latencies);
}
BENCHMARK(BM_ProbeRoundTrip)->Iterations(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The baseline server: bare gRPC, synchronous API like ours.
class BaselineService final : public bench::Baseline::Service {
 public:
  grpc::Status StreamFrames(grpc::ServerContext*, const bench::StreamRequest* request,
                            grpc::ServerWriter<v1::Frame>* writer) override {
    v1::Frame frame = SampleFrame();
    for (int64_t k = 0; k < request->frames(); ++k) {
      frame.set_seq(k);
      if (!writer->Write(frame)) break;
    }
    return grpc::Status::OK;
  }
  grpc::Status PingPong(grpc::ServerContext*,
                        grpc::ServerReaderWriter<v1::Frame, v1::Frame>* stream) override {
    v1::Frame frame;
    while (stream->Read(&frame)) {
      if (!stream->Write(frame)) break;
    }
    return grpc::Status::OK;
  }
  static v1::Frame SampleFrame() {
    v1::Frame frame;
    frame.set_t_s(1.25);
    for (int j = 0; j < 6; ++j) {
      frame.add_q(0.1 * j + 0.123456789);
      frame.add_qd(0.2 * j + 0.987654321);
    }
    frame.mutable_tcp_m()->set_x(0.8);
    frame.mutable_tcp_m()->set_y(0.1);
    frame.mutable_tcp_m()->set_z(1.2);
    return frame;
  }
};

struct Baseline {
  Baseline() {
    grpc::ServerBuilder builder;
    int port = 0;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
    builder.RegisterService(&service);
    server = builder.BuildAndStart();
    stub = bench::Baseline::NewStub(grpc::CreateChannel("127.0.0.1:" + std::to_string(port),
                                                        grpc::InsecureChannelCredentials()));
  }
  ~Baseline() { server->Shutdown(); }
  BaselineService service;
  std::unique_ptr<grpc::Server> server;
  std::unique_ptr<bench::Baseline::Stub> stub;
};

Baseline& BareServer() {
  static Baseline baseline;
  return baseline;
}

void BM_BareStreamFrames(benchmark::State& state) {
  int64_t received = 0;
  for (auto _ : state) {
    grpc::ClientContext context;
    bench::StreamRequest request;
    request.set_frames(100'001);
    auto reader = BareServer().stub->StreamFrames(&context, request);
    v1::Frame frame;
    while (reader->Read(&frame)) ++received;
    reader->Finish();
  }
  state.SetItemsProcessed(received);
}
BENCHMARK(BM_BareStreamFrames)->Unit(benchmark::kMillisecond)->UseRealTime();

// A bare bidi echo of one Frame. range(0) = ms of pause before each echo: 0 is a hot loop
// (the baseline); 10 paces it like BM_ProbeRoundTrip's frames, so that every round
// trip starts from sleeping threads, as a viewer's answer to a paced run does.
void PingPong(benchmark::State& state, std::chrono::milliseconds pause,
              bench::Baseline::Stub& stub) {
  std::vector<double> latencies;
  grpc::ClientContext context;
  auto stream = stub.PingPong(&context);
  v1::Frame frame = BaselineService::SampleFrame(), echo;
  for (auto _ : state) {
    if (pause.count() > 0) std::this_thread::sleep_for(pause);
    const Clock::time_point sent = Clock::now();
    stream->Write(frame);
    stream->Read(&echo);
    latencies.push_back(std::chrono::duration<double, std::micro>(Clock::now() - sent).count());
  }
  stream->WritesDone();
  stream->Finish();
  Percentiles(state, latencies);
}
void BM_BarePingPong(benchmark::State& state) {
  PingPong(state, std::chrono::milliseconds(state.range(0)), *BareServer().stub);
}
BENCHMARK(BM_BarePingPong)->Arg(0)->Iterations(2000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_BarePingPong)->Arg(10)->Iterations(400)->Unit(benchmark::kMicrosecond)->UseRealTime();

// The hot echo with the mbstream server started in the same process, as BM_ControlRoundTrip
// has it: the server's callback-API methods bring gRPC's "nexting" threads (gRPC 1.51, epoll1:
// they poll the process's one epoll set and take sockets' events from the threads that wait on
// them, then hand those over). The like-for-like baseline of a round trip through this server.
void BM_BarePingPongBesideServer(benchmark::State& state) {
  Server();
  PingPong(state, std::chrono::milliseconds(0), *BareServer().stub);
}
BENCHMARK(BM_BarePingPongBesideServer)
    ->Iterations(2000)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

// A PD controller at 1 kHz (h = 1 ms, one RK4 step per period) holding a sine on every joint
// of the IRB 1600 for 10 s of simulated time (10,000 round trips): the time from a command's
// Write to the next state's Read (one period integrated on the server between them), and the
// whole run's simulated seconds per wall second.
void ControlRoundTrip(benchmark::State& state, v1::Simulation::Stub& stub) {
  constexpr double kH = 1e-3, kDuration = 10.0;
  const double kp[6] = {400, 400, 400, 400, 400, 40}, kd[6] = {40, 40, 40, 40, 40, 2};
  v1::ControlStart start;
  start.set_model("irb1600");
  v1::RunSpec& spec = *start.mutable_spec();
  spec.set_duration_s(kDuration);
  spec.set_output_interval_s(0.01);
  spec.set_formulation("joint");
  spec.set_method("rk4");
  spec.set_fixed_step_s(kH);
  for (int i = 0; i < 6; ++i) {
    v1::Drive* drive = spec.add_drives();
    drive->mutable_external()->set_command("effort");
    drive->mutable_external()->set_period_s(kH);
  }
  std::vector<double> latencies;
  double wall_s = 0.0;
  for (auto _ : state) {
    latencies.clear();
    latencies.reserve(10000);
    grpc::ClientContext context;
    auto stream = stub.Control(&context);
    v1::ControlRequest request;
    *request.mutable_start() = start;
    const Clock::time_point begin = Clock::now();
    stream->Write(request);
    v1::ControlResponse response;
    Clock::time_point sent;
    bool first = true;
    while (stream->Read(&response)) {
      if (response.has_ended()) break;
      if (!response.has_state()) continue;
      const v1::ControlState& now = response.state();
      if (!first) {
        latencies.push_back(std::chrono::duration<double, std::micro>(Clock::now() - sent).count());
      }
      first = false;
      if (now.final()) continue;
      v1::ControlRequest command;
      command.mutable_command()->set_step(now.step());
      const double ref = 0.5 * std::sin(M_PI * now.t_s());
      const double rate = 0.5 * M_PI * std::cos(M_PI * now.t_s());
      for (int i = 0; i < 6; ++i) {
        command.mutable_command()->add_values(kp[i] * (ref - now.q(i)) +
                                              kd[i] * (rate - now.qd(i)));
      }
      sent = Clock::now();
      stream->Write(command);
    }
    wall_s = std::chrono::duration<double>(Clock::now() - begin).count();
    stream->WritesDone();
    const grpc::Status status = stream->Finish();
    if (!status.ok() || response.ended().state() != v1::FINISHED) {
      state.SkipWithError(("the controlled run did not finish: " + status.error_message() +
                           response.ended().message())
                              .c_str());
      return;
    }
  }
  Percentiles(state, latencies);
  state.counters["x_real_time"] = kDuration / wall_s;
}
void BM_ControlRoundTrip(benchmark::State& state) { ControlRoundTrip(state, *Server().stub); }
BENCHMARK(BM_ControlRoundTrip)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// The address in environment variable `name` (bench/control_process.sh sets it), or empty.
std::string AddressFrom(const char* name) {
  const char* address = std::getenv(name);
  return address == nullptr ? std::string() : std::string(address);
}

// The round trip with the server in another process (MBSTREAM_BENCH_SERVER): this process
// then has none of the server's threads, as a user's controller has none.
void BM_ControlRoundTripOutOfProcess(benchmark::State& state) {
  const std::string address = AddressFrom("MBSTREAM_BENCH_SERVER");
  if (address.empty()) {
    state.SkipWithError("MBSTREAM_BENCH_SERVER is not set: run bench/control_process.sh");
    return;
  }
  auto stub =
      v1::Simulation::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  ControlRoundTrip(state, *stub);
}
BENCHMARK(BM_ControlRoundTripOutOfProcess)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The hot echo with the echo server in another process (MBSTREAM_BENCH_ECHO, `stream_bench
// --serve-echo`): the like-for-like baseline of BM_ControlRoundTripOutOfProcess.
void BM_BarePingPongOutOfProcess(benchmark::State& state) {
  const std::string address = AddressFrom("MBSTREAM_BENCH_ECHO");
  if (address.empty()) {
    state.SkipWithError("MBSTREAM_BENCH_ECHO is not set: run bench/control_process.sh");
    return;
  }
  auto stub =
      bench::Baseline::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  PingPong(state, std::chrono::milliseconds(0), *stub);
}
BENCHMARK(BM_BarePingPongOutOfProcess)
    ->Iterations(2000)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

// The server's CPU while a controller sleeps: a controlled run waits for a command that comes
// only after 2 s of wall time; the process's CPU time over that sleep (the server is this
// process) per second of it. The worker sleeps on a condition variable (a timed wait that
// also looks at the run's cancel flag 4 times a second), the stream's writer likewise.
void BM_ControlIdleCpu(benchmark::State& state) {
  v1::ControlStart start;
  start.set_model("irb1600");
  v1::RunSpec& spec = *start.mutable_spec();
  spec.set_duration_s(0.01);
  spec.set_control_timeout_s(30);
  for (int i = 0; i < 6; ++i) spec.add_drives()->mutable_external()->set_period_s(1e-3);
  double cpu_per_s = 0.0;
  for (auto _ : state) {
    grpc::ClientContext context;
    auto stream = Server().stub->Control(&context);
    v1::ControlRequest request;
    *request.mutable_start() = start;
    stream->Write(request);
    v1::ControlResponse response;
    while (stream->Read(&response) && !response.has_state()) {
    }
    const auto cpu = [] {
      timespec t;
      clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
      return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
    };
    const double cpu0 = cpu();
    const Clock::time_point wall0 = Clock::now();
    std::this_thread::sleep_for(std::chrono::seconds(2));
    cpu_per_s = (cpu() - cpu0) / std::chrono::duration<double>(Clock::now() - wall0).count();
    context.TryCancel();
    stream->Finish();
  }
  state.counters["cpu_ms_per_s"] = 1e3 * cpu_per_s;
}
BENCHMARK(BM_ControlIdleCpu)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// An ended run of the seed kinematics with `frames` frames (stored once per length).
std::string StoredRun(int64_t frames) {
  static std::map<int64_t, std::string> runs;
  if (auto found = runs.find(frames); found != runs.end()) return found->second;
  v1::RunSpec spec = SeedSpec();
  spec.set_output_interval_s(20.0 / static_cast<double>(frames - 1));
  spec.set_realtime(0.0);
  const std::string id = StartRun(spec);
  for (;;) {
    grpc::ClientContext context;
    v1::GetRunRequest request;
    request.set_run_id(id);
    v1::RunInfo info;
    Server().stub->GetRun(&context, request, &info);
    if (info.state() == v1::FINISHED) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return runs[frames] = id;
}

std::unique_ptr<Stream> Replay(grpc::ClientContext* context, const std::string& run_id,
                               int64_t from_seq, bool wait_for_probes = false) {
  std::unique_ptr<Stream> stream = Server().stub->Subscribe(context);
  v1::SubscribeRequest start;
  start.mutable_start()->set_run_id(run_id);
  start.mutable_start()->set_max_batch(256);
  start.mutable_start()->mutable_replay()->set_speed(0.0);
  start.mutable_start()->mutable_replay()->set_from_seq(from_seq);
  start.mutable_start()->mutable_replay()->set_wait_for_probes(wait_for_probes);
  stream->Write(start);
  return stream;
}

// Reads a replay to its end, answering each frame with `probes` probe reports; returns the
// frames read.
int64_t ReadReplay(Stream& stream, int probes) {
  v1::SubscribeEvent event;
  v1::SubscribeRequest reply;
  int64_t frames = 0;
  while (stream.Read(&event) && !event.has_run_ended()) {
    for (const v1::Frame& frame : event.frames().frames()) {
      ++frames;
      for (int p = 0; p < probes; ++p) {
        v1::ProbeReport* report = reply.mutable_probe();
        report->set_seq(frame.seq());
        report->set_probe(p == 0 ? "tcp" : "probe" + std::to_string(p));
        *report->mutable_position_m() = frame.tcp_m();
        stream.Write(reply);
      }
    }
  }
  stream.WritesDone();
  while (stream.Read(&event)) {
  }
  stream.Finish();
  return frames;
}

// 100,001 stored frames replayed unpaced to range(0) viewers at once (each its own stream and
// thread), each answering every frame with range(1) probes. Items = frames delivered, all
// viewers together; frames_per_s_per_viewer is each viewer's rate.
void BM_ReplayFrames(benchmark::State& state) {
  const int viewers = static_cast<int>(state.range(0));
  const int probes = static_cast<int>(state.range(1));
  const std::string run = StoredRun(100'001);
  int64_t delivered = 0;
  ResetReplayFramesPeak();
  for (auto _ : state) {
    const Clock::time_point begin = Clock::now();
    std::vector<std::thread> threads;
    std::vector<int64_t> counts(viewers, 0);
    for (int v = 0; v < viewers; ++v) {
      threads.emplace_back([&, v] {
        grpc::ClientContext context;
        std::unique_ptr<Stream> stream = Replay(&context, run, 0, probes > 0);
        counts[v] = ReadReplay(*stream, probes);
      });
    }
    for (std::thread& thread : threads) thread.join();
    const double seconds = std::chrono::duration<double>(Clock::now() - begin).count();
    state.SetIterationTime(seconds);
    for (int64_t count : counts) delivered += count;
    state.counters["frames_per_s_per_viewer"] = static_cast<double>(counts[0]) / seconds;
  }
  state.SetItemsProcessed(delivered);
  state.counters["peak_frames_held"] = static_cast<double>(replay_frames_peak());
}
BENCHMARK(BM_ReplayFrames)
    ->Args({1, 0})
    ->Args({1, 1})
    ->Args({10, 0})
    ->Args({10, 1})
    ->Iterations(2)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

// A 1,000,001-frame stored run: from the Subscribe call to the first replayed frame, starting
// at frame range(0); the server holds one stored chunk (4,096 frames) for it.
void BM_ReplayFirstFrame(benchmark::State& state) {
  const std::string run = StoredRun(1'000'001);
  ResetReplayFramesPeak();
  for (auto _ : state) {
    const Clock::time_point begin = Clock::now();
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = Replay(&context, run, state.range(0));
    v1::SubscribeEvent event;
    while (stream->Read(&event) && !event.has_frames()) {
    }
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - begin).count());
    context.TryCancel();
    stream->Finish();
  }
  state.counters["peak_frames_held"] = static_cast<double>(replay_frames_peak());
}
BENCHMARK(BM_ReplayFirstFrame)
    ->Arg(0)
    ->Arg(999'000)
    ->Iterations(20)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

// `stream_bench --serve-echo`: the baseline's echo server alone, on a free loopback port that
// it prints ("127.0.0.1:PORT"), until its standard input closes.
int ServeEcho() {
  BaselineService service;
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
  builder.RegisterService(&service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (server == nullptr || port == 0) return 1;
  std::printf("127.0.0.1:%d\n", port);
  std::fflush(stdout);
  for (int c = std::getchar(); c != EOF; c = std::getchar()) {
  }
  server->Shutdown();
  return 0;
}

}  // namespace
}  // namespace mbstream

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--serve-echo") return mbstream::ServeEcho();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
