#include "server/store/frame_chunks.h"

#include <algorithm>
#include <climits>
#include <utility>

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/util/delimited_message_util.h>

namespace mbstream {

std::vector<EncodedFrameChunk> EncodeFrameChunks(const std::vector<v1::Frame>& frames,
                                                 std::size_t frames_per_chunk) {
  std::vector<EncodedFrameChunk> chunks;
  chunks.reserve((frames.size() + frames_per_chunk - 1) / frames_per_chunk);
  for (std::size_t begin = 0; begin < frames.size(); begin += frames_per_chunk) {
    const std::size_t end = std::min(frames.size(), begin + frames_per_chunk);
    EncodedFrameChunk& chunk = chunks.emplace_back();
    chunk.first_seq = frames[begin].seq();
    chunk.frame_count = static_cast<int64_t>(end - begin);
    {
      google::protobuf::io::StringOutputStream stream(&chunk.data);
      google::protobuf::io::CodedOutputStream coded(&stream);
      for (std::size_t i = begin; i < end; ++i) {
        google::protobuf::util::SerializeDelimitedToCodedStream(frames[i], &coded);
      }
    }  // the coded stream trims the string to what was written when it goes out of scope
  }
  return chunks;
}

void FrameChunkBuilder::Add(const v1::Frame& frame) {
  using google::protobuf::io::CodedOutputStream;
  if (chunk_.frame_count == 0) chunk_.first_seq = frame.seq();
  // The same bytes as SerializeDelimitedToCodedStream, appended in place (the string grows
  // geometrically; a stream per frame would zero-fill its spare capacity every time).
  const size_t size = frame.ByteSizeLong();
  std::string& data = chunk_.data;
  const size_t offset = data.size();
  data.resize(offset + CodedOutputStream::VarintSize32(static_cast<uint32_t>(size)) + size);
  uint8_t* target = reinterpret_cast<uint8_t*>(data.data() + offset);
  target = CodedOutputStream::WriteVarint32ToArray(static_cast<uint32_t>(size), target);
  frame.SerializeWithCachedSizesToArray(target);
  ++chunk_.frame_count;
}

EncodedFrameChunk FrameChunkBuilder::Take() {
  EncodedFrameChunk chunk = std::move(chunk_);
  chunk_ = EncodedFrameChunk();
  return chunk;
}

bool DecodeFrameChunk(std::string_view data, std::vector<v1::Frame>& out) {
  if (data.size() > static_cast<std::size_t>(INT_MAX)) return false;
  google::protobuf::io::CodedInputStream coded(reinterpret_cast<const uint8_t*>(data.data()),
                                               static_cast<int>(data.size()));
  while (true) {
    v1::Frame frame;
    bool clean_eof = false;
    if (!google::protobuf::util::ParseDelimitedFromCodedStream(&frame, &coded, &clean_eof)) {
      return clean_eof;  // clean end of the blob, or a truncated/garbled message
    }
    out.push_back(std::move(frame));
  }
}

}  // namespace mbstream
