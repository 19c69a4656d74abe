#include "server/runs/replica_id.h"

#include <unistd.h>

#include <cstdio>
#include <random>

namespace mbstream {

std::string NewReplicaId() {
  char host[256] = {};
  if (gethostname(host, sizeof(host) - 1) != 0 || host[0] == '\0') {
    std::snprintf(host, sizeof(host), "replica");
  }
  std::mt19937 random(std::random_device{}());
  char suffix[16];
  std::snprintf(suffix, sizeof(suffix), "%04x", static_cast<unsigned>(random() & 0xffff));
  return std::string(host) + "-" + std::to_string(getpid()) + "-" + suffix;
}

}  // namespace mbstream
