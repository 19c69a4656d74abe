#include "tests/common/server_process.h"

#include <algorithm>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace mbstream::testing {

ServerProcess::ServerProcess(const std::string& server_binary, const std::string& data_dir,
                             const std::vector<std::string>& extra_args, const std::string& listen)
    : log_(data_dir + ".log") {
  const std::string& log = log_;
  std::vector<std::string> args = {server_binary, "--listen", listen};
  // A --store among the extra arguments replaces --data (the two exclude each other).
  if (std::find(extra_args.begin(), extra_args.end(), "--store") == extra_args.end()) {
    args.insert(args.end(), {"--data", data_dir});
  }
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  std::remove(log.c_str());  // a previous server's "listening on" line must not be read
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    FILE* out = std::freopen(log.c_str(), "w", stdout);
    if (out == nullptr) _exit(127);
    dup2(fileno(stdout), STDERR_FILENO);
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (address_.empty() && std::chrono::steady_clock::now() < deadline) {
    std::ifstream in(log);
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("listening on ", 0) == 0) address_ = line.substr(13);
    }
    if (address_.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (address_.empty()) {
    Kill();
    throw std::runtime_error("mbstream-server did not report its address; see " + log);
  }
}

ServerProcess::~ServerProcess() { Stop(); }

int ServerProcess::Stop() { return Signal(SIGINT); }

int ServerProcess::Drain() { return Signal(SIGTERM); }

int ServerProcess::Signal(int signal) {
  if (pid_ <= 0) return -1;
  kill(pid_, signal);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return status;
}

void ServerProcess::Kill() {
  if (pid_ <= 0) return;
  kill(pid_, SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return text;
}

std::optional<std::string> WaitForLineIn(const std::string& path, const std::string& marker,
                                         double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  do {
    std::istringstream text(ReadTextFile(path));
    for (std::string line; std::getline(text, line);) {
      const size_t at = line.find(marker);
      if (at != std::string::npos) return line.substr(at + marker.size());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  } while (std::chrono::steady_clock::now() < deadline);
  return std::nullopt;
}

CommandOutcome RunCommand(const std::string& command) {
  CommandOutcome outcome;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return outcome;
  std::array<char, 4096> buffer;
  for (size_t n; (n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0;) {
    outcome.output.append(buffer.data(), n);
  }
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

}  // namespace mbstream::testing
