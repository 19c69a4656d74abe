#include "server/store/store_codec.h"

#include <chrono>

#include "common/check.h"

namespace mbstream {

int64_t UnixNowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string SerializeForStore(const google::protobuf::MessageLite& message, std::string_view what) {
  std::string bytes;
  if (!message.SerializeToString(&bytes)) {
    throw InternalError("store: cannot serialize " + std::string(what) + " (" +
                        std::to_string(message.ByteSizeLong()) + " bytes; the limit is 2 GB)");
  }
  return bytes;
}

void ParseFromStore(std::string_view bytes, google::protobuf::MessageLite& message,
                    std::string_view what, const std::string& path) {
  if (!message.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) {
    throw InternalError("store " + path + ": the stored " + std::string(what) +
                        " is corrupt (cannot parse " + std::to_string(bytes.size()) + " bytes as " +
                        message.GetTypeName() + ")");
  }
}

}  // namespace mbstream
