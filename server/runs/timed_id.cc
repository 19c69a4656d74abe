#include "server/runs/timed_id.h"

#include <cstdio>
#include <ctime>
#include <random>

namespace mbstream {

std::string NewTimedId(std::string_view prefix) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", &utc);
  static thread_local std::mt19937_64 random(std::random_device{}());
  char suffix[16];
  std::snprintf(suffix, sizeof(suffix), "%08x", static_cast<unsigned>(random() & 0xffffffffu));
  return std::string(prefix) + stamp + "-" + suffix;
}

}  // namespace mbstream
