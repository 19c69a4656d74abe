// What both store implementations share: the clock of stored times and the blob codec of
// the proto messages they keep (serialized bytes; columns only for what queries use).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <google/protobuf/message_lite.h>

#include "mbstream/v1/model.pb.h"
#include "mbstream/v1/run.pb.h"

namespace mbstream {

// Milliseconds since the Unix epoch, from the system clock.
int64_t UnixNowMs();

// Serializes `message` for a blob column; throws InternalError when it cannot (a message over
// protobuf's 2 GB limit).
std::string SerializeForStore(const google::protobuf::MessageLite& message, std::string_view what);

// Parses a blob column into `message`; throws InternalError naming `what` (e.g. "run r-1")
// and the database when the stored bytes are corrupt.
void ParseFromStore(std::string_view bytes, google::protobuf::MessageLite& message,
                    std::string_view what, const std::string& path);

// A model's rows as both stores write them: the info (created_unix_ms == 0 replaced by now)
// and the bundle without its assets (they have rows of their own: they may be large meshes).
struct EncodedModel {
  int64_t created_unix_ms = 0;
  std::string info;
  std::string bundle;
};
EncodedModel EncodeModelForStore(const v1::ModelInfo& info, const v1::ModelBundle& bundle);

// What MarkUnfinishedRunsInterrupted does to each unfinished run before writing it back.
void MarkInterrupted(v1::RunInfo& info, const std::string& message, int64_t now_ms);

}  // namespace mbstream
