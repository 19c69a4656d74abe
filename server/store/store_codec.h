// What both store implementations share: the clock of stored times and the blob codec of
// the proto messages they keep (serialized bytes; columns only for what queries use).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <google/protobuf/message_lite.h>

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

}  // namespace mbstream
