#include "server/store/frame_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#if defined(__x86_64__)
#include <nmmintrin.h>
#endif

#include "server/store/disk_full_error.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

std::string SystemError() { return std::strerror(errno); }

// The reflected Castagnoli polynomial, a byte at a time (processors without SSE4.2).
uint32_t Crc32cPortable(std::string_view data) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) != 0 ? (c >> 1) ^ 0x82f63b78u : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t crc = 0xffffffffu;
  for (const unsigned char byte : data) crc = table[(crc ^ byte) & 0xffu] ^ (crc >> 8);
  return ~crc;
}

#if defined(__x86_64__)
__attribute__((target("sse4.2"))) uint32_t Crc32cSse42(std::string_view data) {
  uint64_t crc = 0xffffffffu;
  const char* p = data.data();
  std::size_t n = data.size();
  for (; n >= 8; p += 8, n -= 8) {
    uint64_t word;
    std::memcpy(&word, p, 8);
    crc = _mm_crc32_u64(crc, word);
  }
  auto crc32 = static_cast<uint32_t>(crc);
  for (; n > 0; ++p, --n) crc32 = _mm_crc32_u8(crc32, static_cast<unsigned char>(*p));
  return ~crc32;
}
#endif

}  // namespace

uint32_t Crc32c(std::string_view data) {
#if defined(__x86_64__)
  static const bool sse42 = __builtin_cpu_supports("sse4.2");
  if (sse42) return Crc32cSse42(data);
#endif
  return Crc32cPortable(data);
}

FrameFile::FrameFile(std::string path) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_RDWR | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw InputError("cannot open " + path_ + " for writing (" + SystemError() +
                     "); fix the permissions of the data directory or choose another --data");
  }
}

FrameFile::~FrameFile() {
  if (fd_ >= 0) ::close(fd_);
}

FrameExtent FrameFile::Append(std::string_view data) {
  FrameExtent extent{0, static_cast<int64_t>(data.size()), Crc32c(data)};
  // One write: with O_APPEND the kernel places it at the end of the file as one piece, even
  // when another process appends to the same file, and leaves this descriptor's offset just
  // after it. A short write (a full disk) leaves bytes no row points at.
  ssize_t n;
  do {
    n = ::write(fd_, data.data(), data.size());
  } while (n < 0 && errno == EINTR);
  if (n != static_cast<ssize_t>(data.size())) {
    if (n >= 0 || errno == ENOSPC || errno == EDQUOT) {  // a short write: out of space too
      throw DiskFullError(
          "cannot write frames to " + path_ + " (" +
          (n < 0 ? SystemError()
                 : std::to_string(n) + " of " + std::to_string(data.size()) + " bytes written") +
          "); " + kDiskFullAdvice);
    }
    throw InputError(
        "cannot write frames to " + path_ + " (" +
        (n < 0 ? SystemError()
               : std::to_string(n) + " of " + std::to_string(data.size()) + " bytes written") +
        "); is the disk full?");
  }
  const off_t end = ::lseek(fd_, 0, SEEK_CUR);
  if (end < 0) {
    throw InputError("cannot tell where the frames went in " + path_ + " (" + SystemError() + ")");
  }
  extent.offset = static_cast<int64_t>(end) - extent.bytes;
  return extent;
}

bool FrameFile::Release(int64_t offset, int64_t bytes) {
  if (offset < 0 || bytes <= 0) return bytes == 0;
  return ::fallocate(fd_, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, static_cast<off_t>(offset),
                     static_cast<off_t>(bytes)) == 0;
}

int64_t FrameFile::allocated_bytes() const {
  struct stat status {};
  return ::fstat(fd_, &status) == 0 ? static_cast<int64_t>(status.st_blocks) * 512 : -1;
}

int64_t FrameFile::end() const {
  struct stat status {};
  return ::fstat(fd_, &status) == 0 ? static_cast<int64_t>(status.st_size) : -1;
}

bool FrameFile::Read(const FrameExtent& extent, std::string& out) const {
  // A damaged row's extent is not trusted with an allocation beyond the file.
  if (extent.offset < 0 || extent.bytes < 0 || extent.bytes > end() - extent.offset) return false;
  out.resize(static_cast<std::size_t>(extent.bytes));
  std::size_t read = 0;
  while (read < out.size()) {
    const ssize_t n = ::pread(fd_, out.data() + read, out.size() - read,
                              static_cast<off_t>(extent.offset + static_cast<int64_t>(read)));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;  // an error, or the file ends before the extent
    read += static_cast<std::size_t>(n);
  }
  return Crc32c(out) == extent.crc32c;
}

void FrameFile::Sync() const {
  if (::fdatasync(fd_) != 0) {
    if (errno == ENOSPC || errno == EDQUOT) {
      throw DiskFullError("cannot make the frames in " + path_ + " durable (" + SystemError() +
                          "); " + kDiskFullAdvice);
    }
    throw InputError("cannot make the frames in " + path_ + " durable (" + SystemError() + ")");
  }
}

}  // namespace mbstream
