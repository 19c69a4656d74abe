// A running simulation server: store, model registry, run manager and the gRPC server with
// health checking and reflection. mbstream-server's main and the tests use it.
#pragma once

#include <grpcpp/server.h>

#include <memory>
#include <string>
#include <vector>

#include "server/runs/free_space.h"
#include "server/runs/retention.h"
#include "server/runs/server_limits.h"
#include "shared/net/server_credentials.h"

namespace mbstream {

class Store;
class ModelRegistry;
class RunManager;
class RunDeleter;
class SimulationService;
class Authorizer;
class MetricsEndpoint;
class PeerChannels;
class FreeSpaceWatch;
class StorageKeeper;
class HealthStatus;

struct ServerConfig {
  std::string listen = "127.0.0.1:50051";  // host:port (port 0 = any free) or unix:/path
  std::string data_dir = "mbstream-data";  // SQLite database and nothing else
  // --store: sqlite:DIRECTORY or postgresql://user@host:port/database (store_location.h);
  // empty = the SQLite store in data_dir.
  std::string store;
  std::string store_password_file;  // PostgreSQL's password; empty = PGPASSFILE, ~/.pgpass
  std::string models_dir;           // built-in models (one folder each); empty = none
  ServerLimits limits;
  int max_message_bytes = 64 << 20;  // largest gRPC message either way (raised to hold
                                     // limits.max_model_bytes)
  net::ServerTls tls;                // certificate and key files; empty = insecure
  std::string token_file;            // tokens and roles (see authorizer.h); empty = none
  // Several replicas on one store (docs/cluster.md): the host:port other replicas and
  // clients reach this one at (empty: the listening address; this host's name for a wildcard
  // 0.0.0.0 or [::]), the lease of a run (s) and the
  // time a draining replica gives its runs to end (s).
  std::string advertise;
  double lease_timeout_s = 10.0;
  double grace_s = 30.0;
  // PEM CA trusted for the other replicas' certificates when proxying calls to them (TLS
  // only; peer_channels.h); empty: --tls-client-ca when given, else the system's CAs.
  std::string peer_ca;
  // The name the other replicas' certificates are checked against; empty: the host of their
  // advertised address. For a cluster whose replicas share one certificate (Compose: the
  // advertised host is a container id the certificate cannot name).
  std::string peer_tls_name;
  std::string metrics;  // --metrics host:port serving GET /metrics (port 0 = any); empty = none
  // Retention (retention.h): --retain-runs, --retain-days; a pass every retention_period_s.
  RetentionPolicy retention;
  double retention_period_s = 60.0;
  // The free space of the data directory's disk (SQLite store; free_space.h): empty = statvfs
  // of the data directory (tests give their own), read every free_space_period_s (and by
  // GetStorage, /metrics) for the health service's new-runs status (health_status.h).
  FreeSpaceSource free_space_source;
  double free_space_period_s = 5.0;
};

// What an operator should know about who can reach the server as configured: one sentence
// per exposure (no TLS on a network address, no tokens on a network address). Empty for a
// loopback address or a unix socket, and for a network address with TLS and tokens.
std::vector<std::string> ExposureWarnings(const ServerConfig& config);

class ServerHost {
 public:
  // Opens the store, loads stored and built-in models, marks interrupted runs, starts the
  // workers and listens (a unix socket is made accessible to its owner only). Throws
  // InputError naming what failed (store, address, TLS or token files).
  static std::unique_ptr<ServerHost> Start(const ServerConfig& config);
  ~ServerHost();  // Shutdown()

  // The address clients use: host:port with the port actually bound, or unix:/path.
  const std::string& address() const { return address_; }
  // host:port of the metrics endpoint with the port bound; "" without --metrics.
  std::string metrics_address() const;

  // Interrupts runs (stored as INTERRUPTED), ends streams with UNAVAILABLE, stops
  // listening. Idempotent.
  void Shutdown();
  // Drains (SIGTERM): health NOT_SERVING, no more runs claimed, up to config.grace_s for the
  // runs integrating here to end; then Shutdown(), which hands back (re-queues when the spec
  // has retries left, else INTERRUPTED) what still runs.
  void Drain();
  double grace_s() const { return grace_s_; }  // the drain's limit (config.grace_s)
  // Blocks until Shutdown() has been called (by another thread).
  void Wait();

  RunManager& runs() { return *runs_; }
  // The data directory's free space against --min-free-mb; null on a PostgreSQL store.
  FreeSpaceWatch* free_space() { return free_space_.get(); }

 private:
  ServerHost() = default;
  // The health service's statuses, the free-space watch and /metrics (end of Start).
  void BuildParts(const ServerConfig& config);  // store, models, runs, service...
  // The gRPC server on config.listen (InputError when it cannot listen there).
  void Listen(const ServerConfig& config,
              const std::shared_ptr<grpc::ServerCredentials>& credentials);
  void StartHealthAndMetrics(const ServerConfig& config);
  std::unique_ptr<MetricsEndpoint> metrics_;  // before store_: the store may report to it
  std::unique_ptr<Store> store_;
  std::unique_ptr<ModelRegistry> models_;
  std::unique_ptr<RunManager> runs_;
  std::unique_ptr<RunDeleter> deleter_;  // DeleteRuns, DeleteModel, retention
  std::unique_ptr<Retention> retention_;
  std::unique_ptr<Authorizer> authorizer_;
  std::unique_ptr<PeerChannels> peers_;         // a shared store's other replicas
  std::unique_ptr<FreeSpaceWatch> free_space_;  // SQLite: --min-free-mb, before a run is asked
  std::unique_ptr<StorageKeeper> storage_;      // GetStorage, BackupStorage
  std::unique_ptr<HealthStatus> health_;        // after server_ is built
  std::unique_ptr<SimulationService> service_;
  std::unique_ptr<grpc::Server> server_;
  std::string address_;
  double grace_s_ = 30.0;
  bool shut_down_ = false;
};

}  // namespace mbstream
