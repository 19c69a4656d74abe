// Load and abuse scenarios against a real mbstream-server on loopback (issue 13): many slow
// watchers of a fast run, view tokens writing probes, oversized specs, idle streams, kill -9
// in the middle of a run. Prints one line of figures per scenario (docs/reliability.md) and
// exits 1 when an invariant did not hold, so that its --quick form is also a ctest.
//
//   abuse_load --server build/server/app/mbstream-server [--quick] [--work DIR]
#include <grpcpp/grpcpp.h>
#include <sqlite3.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/spec/run_spec_json.h"
#include "tests/common/server_process.h"

namespace mbstream {
namespace {

using Clock = std::chrono::steady_clock;
using testing::ServerProcess;
namespace fs = std::filesystem;

constexpr char kRunToken[] = "run-token-0123456789abcdef";
constexpr char kViewToken[] = "view-token-0123456789abcdef";

struct Options {
  std::string server;
  std::string work = "/tmp/mbstream-abuse";
  bool quick = false;
};

// A value of /proc/PID/status ("Threads", "VmRSS" in kB, "VmHWM" in kB); -1 if absent.
long ProcStatus(pid_t pid, const std::string& key) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));
  }
  return -1;
}

std::unique_ptr<v1::Simulation::Stub> Connect(const std::string& address) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(256 << 20);
  arguments.SetMaxSendMessageSize(256 << 20);
  return v1::Simulation::NewStub(
      grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), arguments));
}

void Authorize(grpc::ClientContext* context, const char* token) {
  if (token) context->AddMetadata("authorization", std::string("Bearer ") + token);
}

v1::RunSpec SeedSpec() { return LoadRunSpecFile("models/irb1600/seed-run.json"); }

grpc::Status StartRun(v1::Simulation::Stub& stub, const std::string& model, const v1::RunSpec& spec,
                      v1::RunInfo* info, const char* token = nullptr) {
  grpc::ClientContext context;
  Authorize(&context, token);
  v1::StartRunRequest request;
  request.set_model(model);
  *request.mutable_spec() = spec;
  return stub.StartRun(&context, request, info);
}

v1::RunInfo WaitForEnd(v1::Simulation::Stub& stub, const std::string& run_id,
                       const char* token = nullptr) {
  for (;;) {
    grpc::ClientContext context;
    Authorize(&context, token);
    v1::GetRunRequest request;
    request.set_run_id(run_id);
    v1::RunInfo info;
    if (!stub.GetRun(&context, request, &info).ok()) return info;
    if (info.state() != v1::QUEUED && info.state() != v1::RUNNING) return info;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

int64_t StoredProbes(v1::Simulation::Stub& stub, const std::string& run_id, const char* token) {
  grpc::ClientContext context;
  Authorize(&context, token);
  v1::GetResultRequest request;
  request.set_run_id(run_id);
  auto reader = stub.GetResult(&context, request);
  v1::ResultChunk chunk;
  int64_t probes = 0;
  while (reader->Read(&chunk)) probes += chunk.probes_size();
  return reader->Finish().ok() ? probes : -1;
}

bool Report(const char* scenario, bool held, const std::string& figures) {
  std::printf("%-22s %-5s %s\n", scenario, held ? "held" : "BROKE", figures.c_str());
  std::fflush(stdout);
  return held;
}

// Many watchers of one fast run, each reading one message per `pause`: every frame is
// delivered or counted in `missed`, and the final state comes after the last frame.
bool SlowWatchers(const Options& options) {
  const int watchers = options.quick ? 8 : 40;
  const int frames = 40001;
  const auto pause = std::chrono::milliseconds(options.quick ? 2 : 50);
  ServerProcess server(options.server, options.work + "/watchers",
                       {"--max-subscribers", std::to_string(watchers + 8)});
  auto stub = Connect(server.address());
  v1::RunSpec spec = SeedSpec();
  spec.set_output_interval_s(20.0 / (frames - 1));
  v1::RunInfo run;
  if (!StartRun(*stub, "irb1600", spec, &run).ok()) return Report("slow watchers", false, "");
  std::atomic<int> broken{0};
  std::atomic<int64_t> delivered{0}, missed{0};
  const Clock::time_point begin = Clock::now();
  std::vector<std::thread> threads;
  for (int w = 0; w < watchers; ++w) {
    threads.emplace_back([&] {
      grpc::ClientContext context;
      v1::WatchRunRequest request;
      request.set_run_id(run.id());
      request.set_frames(true);
      auto reader = stub->WatchRun(&context, request);
      v1::WatchEvent event;
      int64_t got = 0, lost = 0, first = -1, last = -1;
      bool final_seen = false, ok = true;
      while (reader->Read(&event)) {
        if (event.has_progress()) {
          final_seen = event.progress().state() == v1::FINISHED;
        } else {
          ok = ok && !final_seen;
          lost += event.frames().missed();
          for (const v1::Frame& f : event.frames().frames()) {
            // The first frame pushed (the latest at attach) may itself have been dropped:
            // the first batch's `missed` counts the frames before its first frame.
            if (first < 0) first = f.seq() - event.frames().missed();
            ok = ok && f.seq() > last;
            last = f.seq();
            ++got;
          }
        }
        std::this_thread::sleep_for(pause);
      }
      ok = ok && reader->Finish().ok() && final_seen;
      if (first >= 0) ok = ok && last == frames - 1 && got + lost == frames - first;
      if (!ok) ++broken;
      delivered += got;
      missed += lost;
    });
  }
  for (std::thread& t : threads) t.join();
  const double seconds = std::chrono::duration<double>(Clock::now() - begin).count();
  char figures[256];
  std::snprintf(figures, sizeof(figures),
                "%d watchers x %d frames, one read per %lld ms: %lld delivered, %lld counted "
                "missed, %d broken, %.1f s",
                watchers, frames, static_cast<long long>(pause.count()),
                static_cast<long long>(delivered.load()), static_cast<long long>(missed.load()),
                broken.load(), seconds);
  return Report("slow watchers", broken == 0, figures);
}

// A view token answers frames with probes for another user's run, frames never sent, and
// oversized names: none is stored, and the server's memory does not keep them.
bool ViewTokenProbes(const Options& options) {
  const std::string dir = options.work + "/probes";
  fs::create_directories(dir);
  std::ofstream(dir + "/tokens") << kRunToken << " run,view\n" << kViewToken << " view\n";
  ServerProcess server(options.server, dir + "/data", {"--token-file", dir + "/tokens"});
  auto stub = Connect(server.address());
  v1::RunInfo victim;
  if (!StartRun(*stub, "single_pendulum", v1::RunSpec(), &victim, kRunToken).ok()) {
    return Report("view-token probes", false, "could not start the victim run");
  }
  WaitForEnd(*stub, victim.id(), kRunToken);
  const long rss_before = ProcStatus(server.pid(), "VmRSS");

  grpc::ClientContext context;
  Authorize(&context, kViewToken);
  auto stream = stub->Subscribe(&context);
  v1::SubscribeRequest start;
  start.mutable_start()->set_follow(true);
  stream->Write(start);
  v1::SubscribeEvent event;
  stream->Read(&event);  // subscribed
  v1::RunInfo run;
  StartRun(*stub, "irb1600", SeedSpec(), &run, kRunToken);
  const int fakes = options.quick ? 200 : 2000, huge = options.quick ? 5 : 50;
  int sent = 0;
  while (stream->Read(&event) && !event.has_run_ended()) {
    for (const v1::Frame& f : event.frames().frames()) {
      v1::SubscribeRequest fake;
      v1::ProbeReport* probe = fake.mutable_probe();
      probe->set_seq(f.seq());
      probe->set_probe("fake");
      if (sent < fakes) {  // another user's run
        probe->set_run_id(victim.id());
      } else if (sent < fakes + huge) {  // 4 MiB names
        probe->set_run_id(run.id());
        probe->set_probe(std::string(4 << 20, 'p'));
      } else {  // frames never sent
        probe->set_run_id(run.id());
        probe->set_seq(f.seq() + 1'000'000);
      }
      stream->Write(fake);
      ++sent;
    }
  }
  stream->WritesDone();
  while (stream->Read(&event)) {
  }
  stream->Finish();
  WaitForEnd(*stub, run.id(), kRunToken);
  const int64_t on_victim = StoredProbes(*stub, victim.id(), kRunToken);
  const int64_t on_run = StoredProbes(*stub, run.id(), kRunToken);
  const long rss_after = ProcStatus(server.pid(), "VmRSS");
  char figures[256];
  std::snprintf(figures, sizeof(figures),
                "%d refused reports sent (%d for another run, %d of 4 MiB): %lld stored on the "
                "other run, %lld on this one; RSS %ld -> %ld kB",
                sent, fakes, huge, static_cast<long long>(on_victim),
                static_cast<long long>(on_run), rss_before, rss_after);
  return Report("view-token probes", on_victim == 0 && on_run == 0, figures);
}

// Three runs with a 25 MiB erk_table: refused at the door; the run list still answers.
bool OversizedSpecs(const Options& options) {
  ServerProcess server(options.server, options.work + "/oversized");
  auto stub = Connect(server.address());
  const long rss_before = ProcStatus(server.pid(), "VmRSS");
  int refused = 0;
  for (int i = 0; i < 3; ++i) {
    v1::RunSpec spec = SeedSpec();
    spec.set_erk_table(std::string(25 << 20, 'x'));
    v1::RunInfo info;
    if (StartRun(*stub, "irb1600", spec, &info).error_code() ==
        grpc::StatusCode::INVALID_ARGUMENT) {
      ++refused;
    }
  }
  v1::RunInfo normal;
  StartRun(*stub, "irb1600", SeedSpec(), &normal);
  WaitForEnd(*stub, normal.id());
  grpc::ClientContext context;
  v1::ListRunsResponse response;
  const bool listed = stub->ListRuns(&context, v1::ListRunsRequest(), &response).ok();
  const long rss_after = ProcStatus(server.pid(), "VmRSS");
  char figures[256];
  std::snprintf(figures, sizeof(figures),
                "%d of 3 refused; ListRuns %s (%d runs, %zu bytes); RSS %ld -> %ld kB", refused,
                listed ? "ok" : "FAILED", response.runs_size(), response.ByteSizeLong(), rss_before,
                rss_after);
  return Report("oversized specs", refused == 3 && listed, figures);
}

// 300 Subscribe streams that never send `start`: at most max_subscribers are held (64 by
// default), the rest refused, and they hold no thread (reactors on gRPC's callback API: the
// server's threads grow by a handful at most); after the start deadline all have ended.
bool IdleStreams(const Options& options) {
  // gRPC's callback threads and the stream pump, when the streams come at once.
  constexpr long kHandfulOfThreads = 12;
  const int streams = options.quick ? 100 : 300;
  ServerProcess server(options.server, options.work + "/idle", {"--subscribe-start-s", "2"});
  auto stub = Connect(server.address());
  const long threads_before = ProcStatus(server.pid(), "Threads");
  std::vector<std::unique_ptr<grpc::ClientContext>> contexts;
  std::vector<std::unique_ptr<grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>>>
      open;
  for (int i = 0; i < streams; ++i) {
    contexts.push_back(std::make_unique<grpc::ClientContext>());
    open.push_back(stub->Subscribe(contexts.back().get()));
  }
  long threads_peak = 0;
  int refused = 0, ended = 0;
  std::mutex mutex;
  std::vector<std::thread> finishers;
  for (auto& stream : open) {
    finishers.emplace_back([&, s = stream.get()] {
      v1::SubscribeEvent event;
      while (s->Read(&event)) {
      }
      const grpc::Status status = s->Finish();
      std::lock_guard<std::mutex> lock(mutex);
      if (status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED) {
        ++refused;
      } else {
        ++ended;
      }
      threads_peak = std::max(threads_peak, ProcStatus(server.pid(), "Threads"));
    });
  }
  for (std::thread& t : finishers) t.join();
  long threads_after = ProcStatus(server.pid(), "Threads");
  for (int i = 0; i < 100 && threads_after > threads_before + 8; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // gRPC's idle pollers
    threads_after = ProcStatus(server.pid(), "Threads");
  }
  char figures[256];
  std::snprintf(figures, sizeof(figures),
                "%d idle streams: %d refused, %d ended by the server after 2 s; threads %ld, "
                "peak %ld, after %ld",
                streams, refused, ended, threads_before, threads_peak, threads_after);
  return Report("idle streams", threads_peak <= threads_before + kHandfulOfThreads, figures);
}

// kill -9 while a long run is being integrated and stored: the database is intact and the
// run is INTERRUPTED after a restart.
bool KillDuringStore(const Options& options) {
  const std::string data = options.work + "/kill";
  v1::RunInfo run;
  {
    ServerProcess server(options.server, data);
    auto stub = Connect(server.address());
    v1::RunSpec spec = SeedSpec();
    spec.set_output_interval_s(options.quick ? 1e-4 : 2e-5);  // 200k or 1M frames
    StartRun(*stub, "irb1600", spec, &run);
    for (;;) {
      grpc::ClientContext context;
      v1::GetRunRequest request;
      request.set_run_id(run.id());
      v1::RunInfo now;
      stub->GetRun(&context, request, &now);
      if (now.frames() > now.expected_frames() / 2 || now.state() != v1::RUNNING) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    server.Kill();
  }
  sqlite3* db = nullptr;
  std::string integrity = "not opened";
  if (sqlite3_open_v2((data + "/mbstream.sqlite3").c_str(), &db, SQLITE_OPEN_READONLY, nullptr) ==
      SQLITE_OK) {
    sqlite3_stmt* statement = nullptr;
    sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &statement, nullptr);
    if (sqlite3_step(statement) == SQLITE_ROW) {
      integrity = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
    }
    sqlite3_finalize(statement);
  }
  sqlite3_close(db);
  ServerProcess restarted(options.server, data);
  auto stub = Connect(restarted.address());
  const v1::RunInfo after = WaitForEnd(*stub, run.id());
  char figures[256];
  std::snprintf(figures, sizeof(figures),
                "%lld expected frames, killed past half: integrity_check %s, run %s after restart",
                static_cast<long long>(run.expected_frames()), integrity.c_str(),
                v1::RunState_Name(after.state()).c_str());
  return Report("kill -9 mid-run", integrity == "ok" && after.state() == v1::INTERRUPTED, figures);
}

}  // namespace
}  // namespace mbstream

int main(int argc, char** argv) {
  mbstream::Options options;
  CLI::App app("mbstream load and abuse scenarios against a real server on loopback");
  app.add_option("--server", options.server, "the mbstream-server binary")->required();
  app.add_option("--work", options.work, "scratch folder (emptied first)");
  app.add_flag("--quick", options.quick, "smaller numbers (the ctest form)");
  CLI11_PARSE(app, argc, argv);
  std::filesystem::remove_all(options.work);
  std::filesystem::create_directories(options.work);
  bool held = true;
  held &= mbstream::SlowWatchers(options);
  held &= mbstream::ViewTokenProbes(options);
  held &= mbstream::OversizedSpecs(options);
  held &= mbstream::IdleStreams(options);
  held &= mbstream::KillDuringStore(options);
  std::filesystem::remove_all(options.work);
  return held ? 0 : 1;
}
