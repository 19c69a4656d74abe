#include "server/app/health_status.h"

#include <grpcpp/health_check_service_interface.h>

namespace mbstream {

void HealthStatus::SetServing(bool serving) {
  std::lock_guard lock(mutex_);
  serving_ = serving;
  PublishLocked();
}

void HealthStatus::SetEnoughSpace(bool enough) {
  std::lock_guard lock(mutex_);
  enough_space_ = enough;
  PublishLocked();
}

void HealthStatus::PublishLocked() {
  health_->SetServingStatus(serving_);  // every service known to it, "" among them
  health_->SetServingStatus(kNewRunsHealthService, serving_ && enough_space_);
}

}  // namespace mbstream
