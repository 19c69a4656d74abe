#include "server/runs/free_space.h"

#include <sys/statvfs.h>

#include <cstdio>

#include "server/runs/request_error.h"

namespace mbstream {

namespace {

std::string Mebibytes(int64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  return text;
}

}  // namespace

std::optional<int64_t> FreeBytesAt(const std::string& path) {
  struct statvfs status {};
  if (::statvfs(path.c_str(), &status) != 0) return std::nullopt;
  return static_cast<int64_t>(status.f_bavail) * static_cast<int64_t>(status.f_frsize);
}

void CheckFreeSpace(const FreeSpaceSource& source, int64_t min_free_bytes,
                    const std::string& data_dir) {
  if (min_free_bytes <= 0 || !source) return;
  const std::optional<int64_t> free_bytes = source();
  if (!free_bytes || *free_bytes >= min_free_bytes) return;
  throw RequestError(
      RequestErrorKind::kResourceExhausted,
      "the disk holding the data directory " + data_dir + " has " + Mebibytes(*free_bytes) +
          " free, less than this server's --min-free-mb (" + Mebibytes(min_free_bytes) +
          "): new runs are refused until there is more; free space on that disk (delete runs: "
          "mbstream delete, mbstream-server --retain-runs/--retain-days) or move --data to a "
          "bigger one (the finished runs stay readable)");
}

}  // namespace mbstream
