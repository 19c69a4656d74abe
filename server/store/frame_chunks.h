// How a run's frames are stored: chunks of consecutive frames, each one blob holding a
// sequence of length-delimited serialized v1::Frame (varint size, then the message), the
// format of protobuf's delimited_message_util. One row per chunk keeps rows near 1 MB for
// 6-joint frames while a million-frame run needs only ~250 rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mbstream/v1/frame.pb.h"

namespace mbstream {

// Frames per chunk row. 4096 frames of 6 joints (q, qd, tau, TCP, energies) are ~0.9 MB.
inline constexpr std::size_t kFramesPerChunk = 4096;

struct EncodedFrameChunk {
  int64_t first_seq = 0;    // Frame.seq of the chunk's first frame
  int64_t frame_count = 0;  // frames in `data`
  std::string data;         // length-delimited serialized v1::Frame, in order
};

// Builds one chunk frame by frame, serializing each frame as it is added (a run keeps only
// these bytes, about a quarter of the frames' in-memory size, until the chunk is stored).
class FrameChunkBuilder {
 public:
  void Add(const v1::Frame& frame);
  void Reserve(std::size_t bytes) { chunk_.data.reserve(bytes); }
  int64_t frame_count() const { return chunk_.frame_count; }
  bool empty() const { return chunk_.frame_count == 0; }
  // The chunk built so far; the builder is empty afterwards.
  EncodedFrameChunk Take();
  // The chunk built so far, to be stored, then Clear()ed: the builder keeps its buffer (a run
  // that stores a chunk every second allocates it once, not every second).
  const EncodedFrameChunk& chunk() const { return chunk_; }
  void Clear();

 private:
  EncodedFrameChunk chunk_;
};

// Splits `frames` (in seq order) into chunks of at most `frames_per_chunk` and serializes each.
std::vector<EncodedFrameChunk> EncodeFrameChunks(const std::vector<v1::Frame>& frames,
                                                 std::size_t frames_per_chunk = kFramesPerChunk);

// Appends the serialized frames of one chunk blob to `out`, each as a view of its bytes in
// `data` (without the length prefix), after checking each frame's wire structure (field tags,
// lengths and the blob's framing) without parsing the values: what is sent on as stored
// (GetResult) is not parsed and serialized again. Returns false when the blob is corrupt; the
// frames before the damage are then already appended.
bool SplitFrameChunk(std::string_view data, std::vector<std::string_view>& out);

// Appends the frames of one chunk blob to `out`. Returns false when the blob is corrupt (not a
// sequence of delimited frames); the frames before the damage are then already appended.
bool DecodeFrameChunk(std::string_view data, std::vector<v1::Frame>& out);

}  // namespace mbstream
