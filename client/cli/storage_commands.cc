// `mbstream storage` (GetStorage: what the server's data takes, its free space, runs by state,
// what retention would delete) and `mbstream backup DIR` (BackupStorage: a consistent copy of a
// live SQLite store, written by the server into DIR on its machine). Both need an admin token.
#include <cstdio>
#include <iostream>
#include <string>

#include "client/cli/server_commands.h"

namespace mbstream::cli {

namespace {

std::string Bytes(int64_t bytes) {
  char text[32];
  if (bytes < 0) return "unknown";
  const double b = static_cast<double>(bytes);
  if (bytes < (1 << 10)) {
    std::snprintf(text, sizeof(text), "%lld B", static_cast<long long>(bytes));
  } else if (bytes < (1 << 20)) {
    std::snprintf(text, sizeof(text), "%.1f KiB", b / (1 << 10));
  } else if (bytes < (int64_t{1} << 30)) {
    std::snprintf(text, sizeof(text), "%.1f MiB", b / (1 << 20));
  } else {
    std::snprintf(text, sizeof(text), "%.2f GiB", b / (int64_t{1} << 30));
  }
  return text;
}

void PrintSpace(const v1::GetStorageResponse& s) {
  std::printf("store       %s %s\n", s.backend().c_str(), s.location().c_str());
  std::printf("frames      %s\nprobes      %s\nrun rows    %s\nmodels      %s\n",
              Bytes(s.frame_bytes()).c_str(), Bytes(s.probe_bytes()).c_str(),
              Bytes(s.run_bytes()).c_str(), Bytes(s.model_bytes()).c_str());
  if (s.backend() == "sqlite") std::printf("on disk     %s\n", Bytes(s.disk_bytes()).c_str());
  if (s.free_bytes() >= 0) {
    std::printf("free        %s (--min-free-mb %s)%s\n", Bytes(s.free_bytes()).c_str(),
                Bytes(s.min_free_bytes()).c_str(),
                s.below_min_free() ? ": BELOW, new runs are refused; delete runs (mbstream "
                                     "delete), set retention or give the disk more space"
                                   : "");
  }
}

int Storage(const ClientOptions& client) {
  grpc::ClientContext context;
  v1::GetStorageResponse s;
  const grpc::Status status =
      ConnectSimulation(client)->GetStorage(&context, v1::GetStorageRequest(), &s);
  if (!status.ok()) return ReportRpcError("storage", client, status);
  PrintSpace(s);
  std::cout << "runs       ";
  if (s.runs().empty()) std::cout << " none";
  for (const v1::StorageRunCount& count : s.runs()) {
    std::cout << " " << v1::RunState_Name(count.state()) << " " << count.runs();
  }
  std::cout << "\n";
  bool own = false;  // a model kept by limits of its own
  for (const v1::StorageModelUsage& m : s.models()) own = own || m.own_retention();
  if (s.retain_runs() == 0 && s.retain_days() == 0.0 && !own) {
    std::cout << "retention   none (mbstream-server --retain-runs N, --retain-days D, "
                 "--retain-model MODEL=N,D)\n";
  } else {
    std::cout << "retention   ";
    if (s.retain_runs() > 0 || s.retain_days() > 0.0) {
      std::cout << "newest " << s.retain_runs() << " runs, " << s.retain_days()
                << " days (0 = no limit)";
    } else {
      std::cout << "per model only (--retain-model)";
    }
    std::cout << ": would delete " << s.retention_runs() << " runs, " << Bytes(s.retention_bytes())
              << " now (mbstream retention --dry-run)\n";
  }
  if (s.models().empty()) return 0;
  std::printf("\n%-26s %-16s %6s %12s %12s %12s  %s\n", "MODEL", "NAME", "RUNS", "FRAMES", "PROBES",
              "MODEL", "RETENTION");
  for (const v1::StorageModelUsage& m : s.models()) {
    char own[96] = "the server's";
    if (m.own_retention()) {
      std::snprintf(own, sizeof(own), "newest %d runs, %g days (--retain-model)", m.retain_runs(),
                    m.retain_days());
    }
    std::printf("%-26s %-16s %6lld %12s %12s %12s  %s\n", m.model_id().c_str(),
                m.model_name().c_str(), static_cast<long long>(m.runs()),
                Bytes(m.frame_bytes()).c_str(), Bytes(m.probe_bytes()).c_str(),
                Bytes(m.model_bytes()).c_str(), own);
  }
  return 0;
}

int Backup(const ClientOptions& client, const std::string& dir) {
  grpc::ClientContext context;
  v1::BackupStorageRequest request;
  request.set_dir(dir);
  v1::BackupStorageResponse backup;
  const grpc::Status status = ConnectSimulation(client)->BackupStorage(&context, request, &backup);
  if (!status.ok()) return ReportRpcError("backup", client, status);
  std::printf(
      "backed up %lld runs into %s (database %s, frames %s) in %.2f s; start a server on "
      "it with mbstream-server --data %s\n",
      static_cast<long long>(backup.runs()), backup.dir().c_str(),
      Bytes(backup.database_bytes()).c_str(), Bytes(backup.frames_bytes()).c_str(),
      backup.seconds(), backup.dir().c_str());
  return 0;
}

}  // namespace

void AddStorageCommands(CLI::App& app, std::shared_ptr<const ClientOptions> client,
                        int* exit_code) {
  CLI::App* storage = app.add_subcommand(
      "storage",
      "what the server's data takes (frames, probes, models, on disk), its free space against "
      "--min-free-mb, runs by state and what retention would delete; needs an admin token");
  storage->callback([client, exit_code] { *exit_code = Storage(*client); });

  auto dir = std::make_shared<std::string>();
  CLI::App* backup = app.add_subcommand(
      "backup",
      "a consistent copy of the server's live SQLite store, written by the server into DIR on "
      "its machine (new or empty); mbstream-server --data DIR starts from it; needs an admin "
      "token (PostgreSQL: pg_dump, docs/cluster.md)");
  backup->add_option("dir", *dir, "the directory, on the server's machine")->required();
  backup->callback([client, dir, exit_code] { *exit_code = Backup(*client, *dir); });
}

}  // namespace mbstream::cli
