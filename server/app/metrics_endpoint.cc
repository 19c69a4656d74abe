#include "server/app/metrics_endpoint.h"

#include <limits>
#include <optional>
#include <stdexcept>

#include "server/app/measured_store.h"
#include "server/runs/free_space_watch.h"
#include "server/runs/run_manager.h"
#include "shared/common/check.h"

namespace mbstream {

MetricsEndpoint::MetricsEndpoint() : server_(registry_) {}

MetricsEndpoint::~MetricsEndpoint() { Stop(); }

std::unique_ptr<Store> MetricsEndpoint::Measure(std::unique_ptr<Store> store) {
  return std::make_unique<MeasuredStore>(std::move(store), server_);
}

void MetricsEndpoint::Serve(const std::string& host_port, const RunManager& runs) {
  server_.SetSubscriberCount([&runs] { return static_cast<double>(runs.subscriptions().count()); });
  try {
    listener_ = metrics::HttpListener::Start(host_port, [this] { return registry_.Exposition(); });
  } catch (const std::runtime_error& error) {
    throw InputError(std::string("--metrics: ") + error.what());
  }
}

void MetricsEndpoint::ServeFreeSpace(FreeSpaceWatch& watch) {
  registry_.GaugeFunction(
      "mbstream_store_free_bytes",
      "Free bytes on the disk of the data directory (SQLite store); NaN when unknown", [&watch] {
        watch.Check();  // the health service's new-runs status follows at once
        const std::optional<int64_t> free = watch.free_bytes();
        return free ? static_cast<double>(*free) : std::numeric_limits<double>::quiet_NaN();
      });
  registry_
      .Gauges("mbstream_store_min_free_bytes",
              "--min-free-mb in bytes: below it new runs are refused (0: no check)")
      .With({})
      .Set(static_cast<double>(watch.min_free_bytes()));
}

void MetricsEndpoint::Stop() { listener_.reset(); }

}  // namespace mbstream
