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

void FrameChunkBuilder::Clear() {
  chunk_.first_seq = 0;
  chunk_.frame_count = 0;
  chunk_.data.clear();  // keeps the capacity
}

namespace {

// Skips the fields of one serialized message up to the stream's limit (`coded` limited to
// it). False when a tag, varint or length is malformed or runs past the limit; groups
// (deprecated, never in a Frame) count as malformed.
bool SkipFields(google::protobuf::io::CodedInputStream& coded) {
  using google::protobuf::io::CodedInputStream;
  while (coded.BytesUntilLimit() > 0) {
    const uint32_t tag = coded.ReadTag();
    if ((tag >> 3) == 0) return false;
    uint64_t varint = 0;
    uint32_t length = 0;
    switch (tag & 7) {
      case 0:  // varint
        if (!coded.ReadVarint64(&varint)) return false;
        break;
      case 1:  // 64-bit
        if (!coded.Skip(8)) return false;
        break;
      case 2:  // length-delimited
        if (!coded.ReadVarint32(&length) || !coded.Skip(static_cast<int>(length))) return false;
        break;
      case 5:  // 32-bit
        if (!coded.Skip(4)) return false;
        break;
      default:
        return false;
    }
  }
  return true;
}

}  // namespace

bool SplitFrameChunk(std::string_view data, std::vector<std::string_view>& out) {
  if (data.size() > static_cast<std::size_t>(INT_MAX)) return false;
  google::protobuf::io::CodedInputStream coded(reinterpret_cast<const uint8_t*>(data.data()),
                                               static_cast<int>(data.size()));
  while (static_cast<std::size_t>(coded.CurrentPosition()) < data.size()) {
    uint32_t size = 0;
    if (!coded.ReadVarint32(&size) || size > data.size() - coded.CurrentPosition()) return false;
    const int begin = coded.CurrentPosition();
    const auto limit = coded.PushLimit(static_cast<int>(size));
    if (!SkipFields(coded)) return false;
    coded.PopLimit(limit);
    out.push_back(data.substr(static_cast<std::size_t>(begin), size));
  }
  return true;
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
