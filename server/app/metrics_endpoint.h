// --metrics host:port: the server's metrics registry (server_metrics.h), the store measured
// for it (measured_store.h) and the HTTP listener Prometheus scrapes (GET /metrics).
#pragma once

#include <memory>
#include <string>

#include "server/app/server_metrics.h"
#include "server/metrics/http_listener.h"
#include "server/metrics/metric_registry.h"

namespace mbstream {

class RunManager;
class Store;
class FreeSpaceWatch;

class MetricsEndpoint {
 public:
  MetricsEndpoint();
  ~MetricsEndpoint();  // Stop()

  // `store` wrapped so that its operations, runs, frames and probes are measured.
  std::unique_ptr<Store> Measure(std::unique_ptr<Store> store);
  // Starts serving on host:port (port 0 = any free port); `runs` must outlive Stop(). Throws
  // InputError naming the address when it cannot listen.
  void Serve(const std::string& host_port, const RunManager& runs);
  // Before Serve: mbstream_store_free_bytes (read at each scrape) and
  // mbstream_store_min_free_bytes from `watch`, which must outlive Stop().
  void ServeFreeSpace(FreeSpaceWatch& watch);
  // Stops serving (scrapes in progress finish first). Idempotent.
  void Stop();

  // host:port with the port bound ("" before Serve).
  std::string address() const { return listener_ ? listener_->address() : ""; }
  metrics::Registry& registry() { return registry_; }

 private:
  metrics::Registry registry_;
  ServerMetrics server_;
  std::unique_ptr<metrics::HttpListener> listener_;
};

}  // namespace mbstream
