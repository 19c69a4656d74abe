// What the gRPC health service (grpc.health.v1, gRPC's own implementation) says: the whole
// server ("") SERVING while its store answers and it is not draining or stopping (RunManager's
// serving listener); kNewRunsHealthService SERVING while, besides, the data directory's disk
// has --min-free-mb free (FreeSpaceWatch): below it, new runs are refused (RESOURCE_EXHAUSTED)
// while reads and deletions go on, so the whole server stays SERVING.
#pragma once

#include <mutex>

namespace grpc {
class HealthCheckServiceInterface;
}

namespace mbstream {

// The health service name of "this server accepts new runs" (`mbstream health --service`).
inline constexpr const char* kNewRunsHealthService = "mbstream.new_runs";

class HealthStatus {
 public:
  // `health` is the server's (grpc::Server::GetHealthCheckService) and must outlive this.
  explicit HealthStatus(grpc::HealthCheckServiceInterface* health) : health_(health) {}

  void SetServing(bool serving);
  void SetEnoughSpace(bool enough);

 private:
  void PublishLocked();

  grpc::HealthCheckServiceInterface* health_;
  std::mutex mutex_;
  bool serving_ = true;
  bool enough_space_ = true;
};

}  // namespace mbstream
