#include "server/store/store_codec.h"

#include <chrono>

#include "shared/common/check.h"

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

EncodedModel EncodeModelForStore(const v1::ModelInfo& info, const v1::ModelBundle& bundle) {
  v1::ModelInfo stored_info = info;
  if (stored_info.created_unix_ms() == 0) stored_info.set_created_unix_ms(UnixNowMs());
  v1::ModelBundle bundle_without_assets = bundle;
  bundle_without_assets.clear_assets();
  const std::string what = "model " + info.id();
  return {stored_info.created_unix_ms(), SerializeForStore(stored_info, what),
          SerializeForStore(bundle_without_assets, what + " bundle")};
}

void MarkInterrupted(v1::RunInfo& info, const std::string& message, int64_t now_ms) {
  info.set_state(v1::INTERRUPTED);
  info.set_message(message);
  info.set_ended_unix_ms(now_ms);
  info.set_subscribers(0);
}

}  // namespace mbstream
