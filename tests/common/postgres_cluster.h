// A throwaway PostgreSQL server for tests: initdb into a fresh temporary folder as a non-root
// user (the `postgres` account when the tests run as root), listening on a unix socket in
// that folder only (no TCP), ready when pg_ctl -w returns, stopped and removed on
// destruction. Debian's binaries are found in /usr/lib/postgresql/VERSION/bin (or in
// MBSTREAM_PG_BIN).
#pragma once

#include <string>

namespace mbstream::testing {

class PostgresCluster {
 public:
  // Why no cluster can be started here (binaries or the postgres account missing), or "".
  static std::string Unavailable();

  // Starts the server; throws std::runtime_error with the server's log when it cannot.
  PostgresCluster();
  ~PostgresCluster();  // pg_ctl stop -m fast, then removes the folder
  PostgresCluster(const PostgresCluster&) = delete;
  PostgresCluster& operator=(const PostgresCluster&) = delete;

  // Creates an empty database and returns its URI, postgresql://postgres@SOCKET_DIR/NAME
  // (the socket folder percent-encoded as the host).
  std::string CreateDatabase(const std::string& name);
  // The URI of an existing database (the maintenance database is "postgres").
  std::string Uri(const std::string& database) const;

 private:
  void StartServer(const std::string& log);  // pg_ctl start -w

  std::string bin_;      // folder of initdb, pg_ctl
  std::string folder_;   // data/, socket/, log
  std::string as_user_;  // "runuser -u postgres -- " when root, else ""
};

// The cluster of this test process, started on first use and stopped at exit.
PostgresCluster& SharedPostgresCluster();

}  // namespace mbstream::testing
