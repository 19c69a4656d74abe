// A GetResult message built from bytes already serialized: the stored frames are sent as the
// store holds them, not parsed and serialized again (docs/performance.md, "Many runs at once").
#pragma once

#include <cstddef>
#include <string_view>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"

namespace mbstream {

// The frames and probes of one v1::ResultChunk, each added serialized. They are kept as the
// message's unknown fields under the field numbers of `frames` and `probes` (length-delimited
// either way on the wire), in order, so message() serializes byte for byte as the ResultChunk
// holding them parsed would, and the receiver parses them as frames and probes.
class EncodedResultChunk {
 public:
  // The run's info, sent in the same message as the first frames (one message for a short
  // result): a parsed field, serialized before the frames and probes.
  v1::RunInfo* mutable_info() { return message_.mutable_info(); }
  void AddFrame(std::string_view serialized_frame);
  void AddProbe(const v1::ProbeReport& probe);

  bool empty() const { return items_ == 0 && !message_.has_info(); }
  std::size_t bytes() const { return bytes_; }  // frames and probes added (not the info)
  const v1::ResultChunk& message() const { return message_; }
  void Clear();

 private:
  v1::ResultChunk message_;
  std::size_t items_ = 0;
  std::size_t bytes_ = 0;
};

}  // namespace mbstream
