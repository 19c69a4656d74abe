#include "server/store/sparse_copy.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "server/store/disk_full_error.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// Closes a descriptor on leaving scope.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

[[noreturn]] void ThrowFileError(const std::string& what, const std::string& path) {
  const int error = errno;
  const std::string message = "cannot " + what + " " + path + ": " + std::strerror(error);
  if (error == ENOSPC || error == EDQUOT) throw DiskFullError(message + "; " + kDiskFullAdvice);
  throw InputError(message);
}

// Copies [offset, end) of `in` to the same place in `out`.
void CopyRange(int in, int out, int64_t offset, int64_t end, const std::string& from,
               const std::string& to) {
  std::vector<char> buffer(1 << 20);
  while (offset < end) {
    const size_t want = static_cast<size_t>(std::min<int64_t>(end - offset, buffer.size()));
    const ssize_t n = ::pread(in, buffer.data(), want, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) ThrowFileError("read", from);
    if (n == 0) return;  // the file is shorter: the rest stays a hole
    for (ssize_t written = 0; written < n;) {
      const ssize_t w = ::pwrite(out, buffer.data() + written, static_cast<size_t>(n - written),
                                 static_cast<off_t>(offset + written));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) ThrowFileError("write", to);
      written += w;
    }
    offset += n;
  }
}

}  // namespace

int64_t CopySparse(const std::string& from, const std::string& to, int64_t bytes) {
  Descriptor in{::open(from.c_str(), O_RDONLY | O_CLOEXEC)};
  if (in.fd < 0) ThrowFileError("open", from);
  Descriptor out{::open(to.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600)};
  if (out.fd < 0) ThrowFileError("create", to);
  int64_t copied = 0;
  for (int64_t offset = 0; offset < bytes;) {
    off_t data = ::lseek(in.fd, static_cast<off_t>(offset), SEEK_DATA);
    if (data < 0 && errno == ENXIO) break;            // only a hole is left
    if (data < 0) data = static_cast<off_t>(offset);  // no SEEK_DATA: copy everything
    if (data >= bytes) break;
    off_t hole = ::lseek(in.fd, data, SEEK_HOLE);
    if (hole < 0) hole = static_cast<off_t>(bytes);
    const int64_t end = std::min<int64_t>(hole, bytes);
    CopyRange(in.fd, out.fd, data, end, from, to);
    copied += end - data;
    offset = end;
  }
  if (::ftruncate(out.fd, static_cast<off_t>(bytes)) != 0) ThrowFileError("size", to);
  if (::fsync(out.fd) != 0) ThrowFileError("sync", to);
  return copied;
}

void SyncPath(const std::string& path) {
  Descriptor file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) ThrowFileError("open", path);
  if (::fsync(file.fd) != 0) ThrowFileError("sync", path);
}

}  // namespace mbstream
