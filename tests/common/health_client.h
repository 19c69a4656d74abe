// The health of a server as a client of the standard gRPC health service sees it
// (grpc.health.v1, the overall status: service ""), and a watch that waits for it to change.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "grpc/health/v1/health.grpc.pb.h"

namespace mbstream::testing {

using HealthStatus = grpc::health::v1::HealthCheckResponse::ServingStatus;

// Check: the status, or UNKNOWN when the call failed.
HealthStatus CheckHealth(const std::string& address);

// A Watch stream: each Next() is the next status the server reports (the first one at once).
class HealthWatch {
 public:
  explicit HealthWatch(const std::string& address);
  ~HealthWatch();
  // The next reported status; UNKNOWN when the stream ended (or `deadline_s` passed: a
  // failure guard only).
  HealthStatus Next();
  // Reads statuses until `status` comes; false when the stream ended first.
  bool WaitFor(HealthStatus status);

 private:
  std::unique_ptr<grpc::health::v1::Health::Stub> stub_;
  grpc::ClientContext context_;
  std::unique_ptr<grpc::ClientReader<grpc::health::v1::HealthCheckResponse>> reader_;
};

}  // namespace mbstream::testing
