#include "server/app/server_host.h"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/resource_quota.h>
#include <spdlog/spdlog.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <limits>

#include "server/app/health_status.h"
#include "server/app/metrics_endpoint.h"
#include "server/runs/free_space.h"
#include "server/runs/free_space_watch.h"
#include "server/runs/model_registry.h"
#include "server/runs/run_manager.h"
#include "server/service/authorizer.h"
#include "server/service/peer_channels.h"
#include "server/service/simulation_service.h"
#include "server/service/storage_keeper.h"
#include "server/store/store.h"
#include "server/store/store_location.h"
#include "shared/common/check.h"
#include "shared/net/tls_files.h"

namespace mbstream {

namespace {

// "host:port" -> (host, port); unix addresses have no port.
bool SplitPort(const std::string& address, std::string* host, std::string* port) {
  const size_t colon = address.rfind(':');
  if (address.rfind("unix:", 0) == 0 || colon == std::string::npos) return false;
  *host = address.substr(0, colon);
  *port = address.substr(colon + 1);
  return true;
}

constexpr int kUnaryThreads = 32;  // gRPC threads beyond the streams, for unary calls

bool IsLocal(const std::string& listen) {
  for (const char* prefix : {"unix:", "127.", "localhost:", "[::1]:"}) {
    if (listen.rfind(prefix, 0) == 0) return true;
  }
  return false;
}

}  // namespace

std::vector<std::string> ExposureWarnings(const ServerConfig& config) {
  std::vector<std::string> warnings;
  if (IsLocal(config.listen)) return warnings;
  if (config.tls.cert_file.empty()) {
    warnings.push_back("listening without TLS on a network address (" + config.listen +
                       "): requests, results and tokens cross the network in clear; give "
                       "--tls-cert and --tls-key");
  }
  if (config.token_file.empty()) {
    warnings.push_back("listening without tokens on a network address (" + config.listen +
                       "): anyone who can reach it can submit and run models; give "
                       "--token-file");
  }
  return warnings;
}

namespace {

// Where --store (or --data) puts the store, with its password file read.
StoreLocation StoreLocationOf(const ServerConfig& config) {
  StoreLocation location;
  if (config.store.empty()) {
    location.target = config.data_dir;
  } else {
    location = ParseStoreLocation(config.store);
  }
  if (!config.store_password_file.empty()) {
    if (location.kind != StoreLocation::Kind::kPostgresql) {
      throw InputError(
          "--store-password-file is for a PostgreSQL --store; the SQLite store "
          "has no password");
    }
    location.password = ReadStorePasswordFile(config.store_password_file);
  }
  return location;
}

// How this replica calls the others on a shared store: TLS as its own listener, their CA
// (--peer-ca, else the client CA), and its own certificate where peers require one.
PeerSecurity PeerSecurityOf(const ServerConfig& config) {
  PeerSecurity peer;
  peer.tls = config.tls.enabled();
  peer.ca_file = config.peer_ca.empty() ? config.tls.client_ca_file : config.peer_ca;
  peer.tls_name = config.peer_tls_name;
  if (!config.tls.client_ca_file.empty()) {  // peers require a client certificate
    peer.cert_file = config.tls.cert_file;
    peer.key_file = config.tls.key_file;
  }
  return peer;
}

// gRPC's limits for this server: its handler threads (`quota`), peers' pings, message sizes.
void ApplyGrpcLimits(const ServerConfig& config, grpc::ResourceQuota& quota,
                     grpc::ServerBuilder& builder) {
  // gRPC's handler threads of the synchronous methods (unary calls, GetResult streams);
  // Subscribe and WatchRun are reactors on the callback API and hold none (their count is
  // bounded by max_subscribers). Past this, gRPC refuses new calls with RESOURCE_EXHAUSTED
  // instead of growing.
  quota.SetMaxThreads(config.limits.max_subscribers + kUnaryThreads);
  builder.SetResourceQuota(quota);
  // Other replicas proxying streams here ping idle connections every 20 s (peer_channels.cc).
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS, 10000);
  // A bundle travels in one SubmitModel message (and one GetModel reply): the message limit
  // holds the largest bundle allowed, plus 1 MiB for the other fields and framing.
  const int message_bytes = static_cast<int>(std::min<int64_t>(
      std::numeric_limits<int>::max(),
      std::max<int64_t>(config.max_message_bytes, config.limits.max_model_bytes + (1 << 20))));
  builder.SetMaxReceiveMessageSize(message_bytes);
  builder.SetMaxSendMessageSize(message_bytes);
}

// The address other replicas and followers reach this one at: a wildcard address is no
// address to reach, so this host's name instead (a container's).
std::string AdvertisedAddress(const std::string& name, int port, const std::string& address) {
  char hostname[256] = {};
  const bool wildcard = name == "0.0.0.0" || name == "[::]" || name == "::";
  return wildcard && gethostname(hostname, sizeof(hostname) - 1) == 0
             ? std::string(hostname) + ":" + std::to_string(port)
             : address;
}

}  // namespace

std::unique_ptr<ServerHost> ServerHost::Start(const ServerConfig& config) {
  std::unique_ptr<ServerHost> host(new ServerHost());
  std::shared_ptr<grpc::ServerCredentials> credentials;
  try {
    credentials = net::MakeServerCredentials(config.tls);
  } catch (const net::SecurityConfigError& error) {
    throw InputError(error.what());
  }
  host->BuildParts(config);
  host->Listen(config, credentials);
  host->retention_->Start(config.retention_period_s);  // nothing without --retain-*
  host->StartHealthAndMetrics(config);
  return host;
}

void ServerHost::BuildParts(const ServerConfig& config) {
  authorizer_ = std::make_unique<Authorizer>(config.token_file.empty()
                                                 ? Authorizer::AllowAll()
                                                 : Authorizer::FromTokenFile(config.token_file));
  const StoreLocation location = StoreLocationOf(config);
  store_ = OpenStore(location);
  if (!config.metrics.empty()) {
    metrics_ = std::make_unique<MetricsEndpoint>();
    store_ = metrics_->Measure(std::move(store_));
  }
  models_ = std::make_unique<ModelRegistry>(store_.get(), config.limits);
  const int stored = models_->LoadStored();
  const int builtin = config.models_dir.empty() ? 0 : models_->LoadBuiltins(config.models_dir);
  spdlog::info("{} stored and {} built-in models listed (each compiled when first asked for)",
               stored, builtin);
  ReplicaOptions replica;
  replica.address = config.advertise;
  replica.lease_timeout_s = config.lease_timeout_s;
  replica.private_store = location.kind != StoreLocation::Kind::kPostgresql;
  runs_ =
      std::make_unique<RunManager>(models_.get(), store_.get(), config.limits, nullptr, replica);
  if (location.kind != StoreLocation::Kind::kPostgresql) {  // --min-free-mb: SQLite only
    const std::string dir = location.target;
    FreeSpaceSource source = config.free_space_source;
    if (!source) source = [dir] { return FreeBytesAt(dir); };
    runs_->replica().SetFreeSpaceSource(source, dir);
    free_space_ = std::make_unique<FreeSpaceWatch>(source, config.limits.min_free_bytes);
  }
  grace_s_ = config.grace_s;
  if (replica.private_store) {
    if (!config.peer_ca.empty()) {
      throw InputError("--peer-ca is for replicas sharing a PostgreSQL --store; this one has none");
    }
  } else {
    try {
      peers_ = std::make_unique<PeerChannels>(PeerSecurityOf(config), runs_->replica().id());
    } catch (const net::SecurityConfigError& error) {
      throw InputError(error.what());
    }
  }
  deleter_ = std::make_unique<RunDeleter>(store_.get(), runs_.get(), models_.get());
  retention_ = std::make_unique<Retention>(store_.get(), deleter_.get(), config.retention);
  storage_ = std::make_unique<StorageKeeper>(StorageSetup{
      store_.get(), replica.private_store, replica.private_store ? location.target : store_->path(),
      models_.get(), retention_.get(), free_space_.get()});
  service_ = std::make_unique<SimulationService>(
      models_.get(), runs_.get(), authorizer_.get(), peers_.get(),
      DataKeeping{deleter_.get(), retention_.get(), storage_.get()});
}

void ServerHost::Listen(const ServerConfig& config,
                        const std::shared_ptr<grpc::ServerCredentials>& credentials) {
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(config.listen, credentials, &port);
  builder.RegisterService(service_.get());
  grpc::ResourceQuota quota("mbstream-server");
  ApplyGrpcLimits(config, quota, builder);
  // A unix socket is created owner-only (the umask applies while gRPC binds it).
  const bool unix_socket = config.listen.rfind("unix:", 0) == 0;
  const mode_t previous_mask = unix_socket ? umask(0077) : 0;
  server_ = builder.BuildAndStart();
  if (unix_socket) umask(previous_mask);
  std::string name, port_text;
  const bool has_port = SplitPort(config.listen, &name, &port_text);
  if (!server_ || (has_port && port == 0)) {
    runs_->replica().Shutdown("the server could not start");
    throw InputError("cannot listen on " + config.listen +
                     ": is the address valid and the port free? (use port 0 for any free port)");
  }
  address_ = has_port ? name + ":" + std::to_string(port) : config.listen;
  if (config.advertise.empty()) {
    runs_->replica().SetAdvertisedAddress(AdvertisedAddress(name, port, address_));
  }
}

void ServerHost::StartHealthAndMetrics(const ServerConfig& config) {
  // grpc.health.v1: SERVING while the store answers and the replica is not draining; new runs
  // besides while the data directory's disk has --min-free-mb free (health_status.h).
  health_ = std::make_unique<HealthStatus>(server_->GetHealthCheckService());
  HealthStatus* health = health_.get();
  runs_->replica().SetServingListener([health](bool serving) { health->SetServing(serving); });
  if (free_space_) {
    free_space_->SetListener([health](bool enough) { health->SetEnoughSpace(enough); });
    free_space_->Start(config.free_space_period_s);
  }
  if (metrics_) {
    if (free_space_) metrics_->ServeFreeSpace(*free_space_);
    metrics_->Serve(config.metrics, *runs_);
  }
}

ServerHost::~ServerHost() {
  if (metrics_) metrics_->Stop();  // a scrape reads the run manager
  Shutdown();
}

std::string ServerHost::metrics_address() const { return metrics_ ? metrics_->address() : ""; }

void ServerHost::Shutdown() {
  if (shut_down_ || !server_) return;  // not started (Start threw) or already stopped
  shut_down_ = true;
  if (free_space_) free_space_->Stop();  // it tells the health service
  spdlog::info("shutting down: interrupting runs and closing streams");
  service_->Stop();
  retention_->Stop();
  runs_->replica().Shutdown("the server was shut down");
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(2));
}

void ServerHost::Drain() {
  if (shut_down_ || !server_) return;
  runs_->replica().Drain(std::chrono::duration<double>(grace_s_),
                         "the server was drained (SIGTERM)");
  Shutdown();
}

void ServerHost::Wait() { server_->Wait(); }

}  // namespace mbstream
