// A real mbstream-server process for end-to-end tests: started on port 0 with a data
// directory, its address read from its "listening on ADDR" line; stopped with SIGINT (at once,
// runs INTERRUPTED), drained with SIGTERM, or killed with SIGKILL to simulate a crash.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace mbstream::testing {

class ServerProcess {
 public:
  // Starts `server_binary --listen LISTEN --data data_dir` plus `extra_args`; waits up to
  // 30 s for its address. The log goes to log_path() = data_dir + ".log". With "--store" in
  // `extra_args`, --data is left out.
  ServerProcess(const std::string& server_binary, const std::string& data_dir,
                const std::vector<std::string>& extra_args = {},
                const std::string& listen = "127.0.0.1:0");
  ~ServerProcess();  // Stop()

  const std::string& address() const { return address_; }
  const std::string& log_path() const { return log_; }
  pid_t pid() const { return pid_; }
  // SIGINT and wait; returns the exit status (as from waitpid), -1 if already stopped.
  int Stop();
  // SIGTERM (the server drains: its runs get --grace-s to end) and wait; as Stop.
  int Drain();
  // SIGKILL and wait: a crash.
  void Kill();

 private:
  int Signal(int signal);  // sends it and waits
  pid_t pid_ = -1;
  std::string address_;
  std::string log_;
};

// Runs a shell command; returns its exit code (-1 when killed) and its stdout+stderr.
struct CommandOutcome {
  int exit_code = -1;
  std::string output;
};
CommandOutcome RunCommand(const std::string& command);

// A file's whole text ("" when it cannot be read).
std::string ReadTextFile(const std::string& path);

// Waits up to `timeout_s` for a line of the file at `path` (a growing log) that contains
// `marker`; returns what follows the marker on that line, or nullopt.
std::optional<std::string> WaitForLineIn(const std::string& path, const std::string& marker,
                                         double timeout_s = 30.0);

}  // namespace mbstream::testing
