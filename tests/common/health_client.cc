#include "tests/common/health_client.h"

#include <chrono>

namespace mbstream::testing {

using grpc::health::v1::Health;
using grpc::health::v1::HealthCheckRequest;
using grpc::health::v1::HealthCheckResponse;

namespace {

std::unique_ptr<Health::Stub> StubFor(const std::string& address) {
  return Health::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
}

}  // namespace

HealthStatus CheckHealth(const std::string& address) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  HealthCheckResponse response;
  if (!StubFor(address)->Check(&context, HealthCheckRequest(), &response).ok()) {
    return HealthCheckResponse::UNKNOWN;
  }
  return response.status();
}

HealthWatch::HealthWatch(const std::string& address) : stub_(StubFor(address)) {
  // A failure guard only: the tests wait for the status to change, never for time.
  context_.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(90));
  reader_ = stub_->Watch(&context_, HealthCheckRequest());
}

HealthWatch::~HealthWatch() {
  context_.TryCancel();
  reader_->Finish();
}

HealthStatus HealthWatch::Next() {
  HealthCheckResponse response;
  return reader_->Read(&response) ? response.status() : HealthCheckResponse::UNKNOWN;
}

bool HealthWatch::WaitFor(HealthStatus status) {
  for (;;) {
    const HealthStatus next = Next();
    if (next == status) return true;
    if (next == HealthCheckResponse::UNKNOWN) return false;
  }
}

}  // namespace mbstream::testing
