#include "tests/common/postgres_cluster.h"

#include <pwd.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <system_error>

#include <pqxx/pqxx>

#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;

// The newest /usr/lib/postgresql/VERSION/bin holding initdb and pg_ctl, or "".
std::string FindBinaries() {
  std::error_code error;
  if (const char* bin = std::getenv("MBSTREAM_PG_BIN"); bin != nullptr) {
    return fs::exists(fs::path(bin) / "initdb", error) ? bin : "";
  }
  std::string best;
  for (const auto& entry : fs::directory_iterator("/usr/lib/postgresql", error)) {
    const fs::path bin = entry.path() / "bin";
    if (fs::exists(bin / "initdb", error) && fs::exists(bin / "pg_ctl", error) &&
        bin.string() > best) {
      best = bin.string();
    }
  }
  return best;
}

std::string PercentEncoded(const std::string& text) {
  std::string out;
  constexpr char kHex[] = "0123456789ABCDEF";
  for (const unsigned char c : text) {
    if (std::isalnum(c) != 0 || c == '-' || c == '_' || c == '.') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 0xf];
    }
  }
  return out;
}

void Run(const std::string& command, const std::string& log) {
  const CommandOutcome outcome = RunCommand(command);
  if (outcome.exit_code != 0) {
    throw std::runtime_error("test PostgreSQL: `" + command + "` failed (" +
                             std::to_string(outcome.exit_code) + "): " + outcome.output +
                             ReadTextFile(log));
  }
}

}  // namespace

std::string PostgresCluster::Unavailable() {
  if (FindBinaries().empty()) {
    return "PostgreSQL's server binaries are not installed (Debian: apt-get install postgresql)";
  }
  if (::geteuid() == 0 && ::getpwnam("postgres") == nullptr) {
    return "running as root and there is no postgres account to run PostgreSQL as";
  }
  return "";
}

PostgresCluster::PostgresCluster() : bin_(FindBinaries()) {
  // A folder no other process can have: named by the process id, a folder left behind by a
  // killed test would be reused by the next process given the same id (ids wrap at 32768).
  std::string name = (fs::temp_directory_path() / "mbstream-pg-XXXXXX").string();
  if (::mkdtemp(name.data()) == nullptr) {
    throw std::runtime_error("test PostgreSQL: cannot make a folder " + name);
  }
  folder_ = name;
  fs::create_directories(folder_ + "/socket");
  if (::geteuid() == 0) {
    const passwd* account = ::getpwnam("postgres");
    if (account == nullptr) throw std::runtime_error(Unavailable());
    for (const std::string& path : {folder_, folder_ + "/socket"}) {
      if (::chown(path.c_str(), account->pw_uid, account->pw_gid) != 0) {
        throw std::runtime_error("test PostgreSQL: cannot chown " + path);
      }
    }
    as_user_ = "runuser -u postgres -- ";
  }
  const std::string log = folder_ + "/log";
  // initdb's result depends only on the binaries and the options: it is made once per user
  // and binaries, into a folder renamed into place whole (a test running at the same time
  // sees all of it or none and then makes its own), and copied for each cluster, which takes
  // a tenth of initdb's time.
  std::string key = bin_;
  for (char& c : key) c = std::isalnum(static_cast<unsigned char>(c)) != 0 ? c : '_';
  const std::string cached =
      (fs::temp_directory_path() / ("mbstream-pg-initdb-" + std::to_string(::geteuid()) + key))
          .string();
  std::error_code error;
  if (fs::exists(cached + "/PG_VERSION", error)) {
    Run("cp -a " + cached + " " + folder_ + "/data", log);
    StartServer(log);
    return;
  }
  Run(as_user_ + bin_ + "/initdb -D " + folder_ + "/data -U postgres --auth=trust -E UTF8 " +
          "--locale=C --no-sync --no-instructions",
      log);
  const std::string staging = folder_ + "/initdb-copy";
  Run("cp -a " + folder_ + "/data " + staging, log);
  fs::rename(staging, cached, error);  // fails when another test was first: keep its copy
  if (error) fs::remove_all(staging, error);
  StartServer(log);
}

void PostgresCluster::StartServer(const std::string& log) {
  // -w: pg_ctl returns once the server accepts connections (an event, not a sleep).
  Run(as_user_ + bin_ + "/pg_ctl -D " + folder_ + "/data -w -s -l " + log +
          " -o \"-c listen_addresses='' -k " + folder_ + "/socket -c fsync=off\" start",
      log);
}

PostgresCluster::~PostgresCluster() {
  RunCommand(as_user_ + bin_ + "/pg_ctl -D " + folder_ + "/data -w -s -m fast stop");
  std::error_code ignored;
  fs::remove_all(folder_, ignored);
}

std::string PostgresCluster::Uri(const std::string& database) const {
  return "postgresql://postgres@" + PercentEncoded(folder_ + "/socket") + "/" + database;
}

std::string PostgresCluster::CreateDatabase(const std::string& name) {
  pqxx::connection maintenance(Uri("postgres"));
  pqxx::nontransaction tx(maintenance);
  tx.exec("CREATE DATABASE " + tx.quote_name(name));
  return Uri(name);
}

PostgresCluster& SharedPostgresCluster() {
  static const std::unique_ptr<PostgresCluster> cluster = std::make_unique<PostgresCluster>();
  return *cluster;
}

}  // namespace mbstream::testing
