// Peak and resident memory of a real mbstream-server process against a run's length
// (docs/performance.md, "Memory of long runs"). For each frame count N it starts a fresh
// server with an empty data directory, then
//   idle      VmRSS before the run,
//   run       VmHWM while the run integrates and is stored (the seed experiment, kinematic,
//             output every 1 ms for N ms: N + 1 frames),
//   after     VmRSS once the run ended,
//   result    VmHWM while a client reads the whole result with GetResult,
//   end       VmRSS after that,
// and prints one CSV row per N. `idle` is taken after a warm-up (a short run and its result). The
// peak is reset between phases through /proc/PID/clear_refs ("5"). Usage:
//   run_memory --server build/server/app/mbstream-server [--frames 10000,100000,1000000]
// With --model-mb M it measures a stored model instead: VmRSS idle, after submitting a model
// with an M MiB mesh, after a restart of the server on the same data, and after a run of it.
//   run_memory --server build/server/app/mbstream-server --model-mb 60
#include <grpcpp/grpcpp.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/spec/run_spec_json.h"

extern char** environ;

namespace {

namespace v1 = mbstream::v1;

// A field of /proc/PID/status in MB ("VmRSS", "VmHWM").
double StatusMb(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field + ":", 0) == 0) {
      std::istringstream value(line.substr(field.size() + 1));
      double kb = 0;
      value >> kb;
      return kb / 1024.0;
    }
  }
  throw std::runtime_error("no " + field + " in /proc/" + std::to_string(pid) + "/status");
}

void ResetPeak(pid_t pid) {
  std::ofstream out("/proc/" + std::to_string(pid) + "/clear_refs");
  out << "5";
}

struct Server {
  pid_t pid = 0;
  std::string address;
};

Server StartServer(const std::string& binary, const std::string& data, const std::string& models) {
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) throw std::runtime_error("pipe failed");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  std::vector<std::string> args = {binary,     "--listen", "127.0.0.1:0", "--data", data,
                                   "--models", models,     "--log-level", "warn"};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  Server server;
  if (posix_spawn(&server.pid, binary.c_str(), &actions, nullptr, argv.data(), environ) != 0) {
    throw std::runtime_error("cannot start " + binary);
  }
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_fds[1]);
  FILE* out = fdopen(pipe_fds[0], "r");
  char line[512];
  while (std::fgets(line, sizeof(line), out) != nullptr) {
    const std::string text(line);
    if (text.rfind("listening on ", 0) == 0) {
      server.address = text.substr(13, text.find_last_not_of("\r\n") - 12);
      break;
    }
  }
  if (server.address.empty()) throw std::runtime_error(binary + " did not print its address");
  std::thread([out] {  // drain the rest of its stdout
    char rest[512];
    while (std::fgets(rest, sizeof(rest), out) != nullptr) {
    }
    std::fclose(out);
  })
      .detach();
  return server;
}

v1::RunInfo GetRun(v1::Simulation::Stub& stub, const std::string& id) {
  grpc::ClientContext context;
  v1::GetRunRequest request;
  request.set_run_id(id);
  v1::RunInfo info;
  const grpc::Status status = stub.GetRun(&context, request, &info);
  if (!status.ok()) throw std::runtime_error("GetRun: " + status.error_message());
  return info;
}

bool Final(v1::RunState state) {
  return state != v1::QUEUED && state != v1::RUNNING && state != v1::RUN_STATE_UNSPECIFIED;
}

v1::RunInfo StartRun(v1::Simulation::Stub& stub, const v1::RunSpec& spec) {
  grpc::ClientContext context;
  v1::StartRunRequest request;
  request.set_model("irb1600");
  *request.mutable_spec() = spec;
  v1::RunInfo info;
  const grpc::Status status = stub.StartRun(&context, request, &info);
  if (!status.ok()) throw std::runtime_error("StartRun: " + status.error_message());
  return info;
}

v1::RunInfo WaitForEnd(v1::Simulation::Stub& stub, const std::string& id) {
  v1::RunInfo info = GetRun(stub, id);
  while (!Final(info.state())) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    info = GetRun(stub, id);
  }
  return info;
}

// Reads a whole result, keeping nothing; returns (messages, frames).
std::pair<int, long> ReadResult(v1::Simulation::Stub& stub, const std::string& id) {
  grpc::ClientContext context;
  v1::GetResultRequest request;
  request.set_run_id(id);
  auto reader = stub.GetResult(&context, request);
  v1::ResultChunk chunk;
  int messages = 0;
  long frames = 0;
  while (reader->Read(&chunk)) {
    ++messages;
    frames += chunk.frames_size();
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok()) throw std::runtime_error("GetResult: " + status.error_message());
  return {messages, frames};
}

// One moving link drawn with a mesh of `mb` MiB.
v1::ModelBundle MeshBundle(long mb) {
  v1::ModelBundle bundle;
  bundle.set_urdf(R"(<robot name="heavy">
  <link name="base"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="arm">
    <inertial><mass value="1"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="package://heavy/meshes/arm.stl"/></geometry></visual>
  </link>
</robot>
)");
  v1::Asset* asset = bundle.add_assets();
  asset->set_name("arm.stl");
  asset->set_data(std::string(static_cast<size_t>(mb) << 20, 'x'));
  return bundle;
}

int MeasureStoredModel(const std::string& binary, const std::string& source, long mb) {
  const std::filesystem::path data =
      std::filesystem::temp_directory_path() / ("run_memory_model_" + std::to_string(getpid()));
  std::filesystem::remove_all(data);
  grpc::ChannelArguments arguments;
  arguments.SetMaxSendMessageSize(256 << 20);
  std::string model_id;
  std::printf("phase,rss_mb\n");
  for (int start = 0; start < 2; ++start) {
    const Server server = StartServer(binary, data.string(), source + "/models");
    auto stub = v1::Simulation::NewStub(
        grpc::CreateCustomChannel(server.address, grpc::InsecureChannelCredentials(), arguments));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    std::printf("%s,%.1f\n", start == 0 ? "idle" : "after restart", StatusMb(server.pid, "VmRSS"));
    if (start == 0) {
      grpc::ClientContext context;
      v1::SubmitModelRequest request;
      *request.mutable_bundle() = MeshBundle(mb);
      v1::ModelInfo info;
      const grpc::Status status = stub->SubmitModel(&context, request, &info);
      if (!status.ok()) {
        std::cerr << "SubmitModel: " << status.error_message() << "\n";
        kill(server.pid, SIGTERM);
        waitpid(server.pid, nullptr, 0);
        return 1;
      }
      model_id = info.id();
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      std::printf("after submitting %ld MiB,%.1f\n", mb, StatusMb(server.pid, "VmRSS"));
    } else {
      grpc::ClientContext context;
      v1::StartRunRequest request;
      request.set_model(model_id);
      request.mutable_spec()->set_duration_s(0.1);
      request.mutable_spec()->set_output_interval_s(0.05);
      v1::RunInfo info;
      const grpc::Status status = stub->StartRun(&context, request, &info);
      if (status.ok()) WaitForEnd(*stub, info.id());
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      std::printf("after a run of it,%.1f\n", StatusMb(server.pid, "VmRSS"));
    }
    kill(server.pid, SIGTERM);
    waitpid(server.pid, nullptr, 0);
  }
  std::filesystem::remove_all(data);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string binary;
  std::vector<long> counts = {10000, 100000, 1000000};
  long model_mb = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--server") {
      binary = argv[i + 1];
    } else if (flag == "--model-mb") {
      model_mb = std::stol(argv[i + 1]);
    } else if (flag == "--frames") {
      counts.clear();
      std::stringstream list(argv[i + 1]);
      for (std::string item; std::getline(list, item, ',');) counts.push_back(std::stol(item));
    }
  }
  if (binary.empty()) {
    std::cerr << "usage: run_memory --server PATH/mbstream-server [--frames N,N,...]\n";
    return 2;
  }
  const std::string source = MBSTREAM_SOURCE_DIR;
  if (model_mb > 0) return MeasureStoredModel(binary, source, model_mb);
  std::cout << "frames,idle_mb,run_peak_mb,after_run_mb,result_peak_mb,after_result_mb,"
               "result_messages\n";
  for (const long frames : counts) {
    const std::filesystem::path data =
        std::filesystem::temp_directory_path() / ("run_memory_" + std::to_string(getpid()));
    std::filesystem::remove_all(data);
    const Server server = StartServer(binary, data.string(), source + "/models");
    try {
      grpc::ChannelArguments arguments;
      arguments.SetMaxReceiveMessageSize(256 << 20);
      auto stub = v1::Simulation::NewStub(
          grpc::CreateCustomChannel(server.address, grpc::InsecureChannelCredentials(), arguments));

      // Warm up (a 401-frame run and its result: gRPC's threads and buffers, SQLite's cache),
      // then take the idle value.
      v1::RunSpec spec = mbstream::LoadRunSpecFile(source + "/models/irb1600/seed-run.json");
      ReadResult(*stub, WaitForEnd(*stub, StartRun(*stub, spec).id()).id());
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      const double idle = StatusMb(server.pid, "VmRSS");
      ResetPeak(server.pid);
      spec.set_output_interval_s(1e-3);
      spec.set_duration_s(static_cast<double>(frames) * 1e-3);
      const v1::RunInfo info = WaitForEnd(*stub, StartRun(*stub, spec).id());
      const double run_peak = StatusMb(server.pid, "VmHWM");
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      const double after_run = StatusMb(server.pid, "VmRSS");

      ResetPeak(server.pid);
      const auto [messages, received] = ReadResult(*stub, info.id());
      const double result_peak = StatusMb(server.pid, "VmHWM");
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      const double after_result = StatusMb(server.pid, "VmRSS");
      if (std::getenv("RUN_MEMORY_EXTRA") != nullptr) {
        v1::RunSpec small = mbstream::LoadRunSpecFile(source + "/models/irb1600/seed-run.json");
        WaitForEnd(*stub, StartRun(*stub, small).id());
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        std::fprintf(stderr, "after one more short run: %.1f MB\n", StatusMb(server.pid, "VmRSS"));
      }
      if (std::getenv("RUN_MEMORY_SMAPS") != nullptr) {  // diagnosis: the largest mappings
        std::system(
            ("awk '/^[0-9a-f]+-/{name=$6\" \"$1} /^Rss:/{if ($2>500) print $2\" kB \"name}' "
             "/proc/" +
             std::to_string(server.pid) + "/smaps | sort -rn | head -12 >&2")
                .c_str());
      }
      if (received != info.frames()) {
        std::cerr << "GetResult returned " << received << " of " << info.frames() << " frames\n";
      }
      std::printf("%ld,%.1f,%.1f,%.1f,%.1f,%.1f,%d\n", static_cast<long>(info.frames()), idle,
                  run_peak, after_run, result_peak, after_result, messages);
      std::fflush(stdout);
    } catch (const std::exception& error) {
      std::cerr << "run_memory: " << error.what() << "\n";
      kill(server.pid, SIGTERM);
      waitpid(server.pid, nullptr, 0);
      return 1;
    }
    kill(server.pid, SIGTERM);
    waitpid(server.pid, nullptr, 0);
    std::filesystem::remove_all(data);
  }
  return 0;
}
