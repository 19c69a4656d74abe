#include "server/app/metrics_endpoint.h"

#include <stdexcept>

#include "common/check.h"
#include "server/app/measured_store.h"
#include "server/runs/run_manager.h"

namespace mbstream {

MetricsEndpoint::MetricsEndpoint() : server_(registry_) {}

MetricsEndpoint::~MetricsEndpoint() { Stop(); }

std::unique_ptr<Store> MetricsEndpoint::Measure(std::unique_ptr<Store> store) {
  return std::make_unique<MeasuredStore>(std::move(store), server_);
}

void MetricsEndpoint::Serve(const std::string& host_port, const RunManager& runs) {
  server_.SetSubscriberCount([&runs] { return static_cast<double>(runs.subscriber_count()); });
  try {
    listener_ = metrics::HttpListener::Start(host_port, [this] { return registry_.Exposition(); });
  } catch (const std::runtime_error& error) {
    throw InputError(std::string("--metrics: ") + error.what());
  }
}

void MetricsEndpoint::Stop() { listener_.reset(); }

}  // namespace mbstream
