#include "server/mcap/mcap_sink.h"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream::mcap {

McapFileSink::McapFileSink(std::string path)
    : path_(std::move(path)), temporary_path_(path_ + ".tmp") {
  file_ = std::fopen(temporary_path_.c_str(), "wb");
  if (file_ == nullptr) {
    throw InputError(
        FormatString("cannot write the MCAP file %s: %s; check that its folder "
                     "exists and is writable",
                     temporary_path_.c_str(), std::strerror(errno)));
  }
}

McapFileSink::~McapFileSink() {
  if (file_ != nullptr) std::fclose(file_);
  if (!closed_) {
    std::error_code error;
    std::filesystem::remove(temporary_path_, error);
  }
}

void McapFileSink::Write(std::string_view bytes) {
  MBSTREAM_CHECK(file_ != nullptr);
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    throw InputError(FormatString("cannot write the MCAP file %s: %s (is the disk full?)",
                                  temporary_path_.c_str(), std::strerror(errno)));
  }
}

void McapFileSink::Close() {
  MBSTREAM_CHECK(file_ != nullptr);
  const bool flushed = std::fflush(file_) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!flushed || !closed) {
    throw InputError(FormatString("cannot write the MCAP file %s: %s (is the disk full?)",
                                  temporary_path_.c_str(), std::strerror(errno)));
  }
  std::error_code error;
  std::filesystem::rename(temporary_path_, path_, error);
  if (error) {
    throw InputError(FormatString("cannot rename %s to %s: %s", temporary_path_.c_str(),
                                  path_.c_str(), error.message().c_str()));
  }
  closed_ = true;
}

}  // namespace mbstream::mcap
