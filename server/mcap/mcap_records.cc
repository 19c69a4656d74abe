#include "server/mcap/mcap_records.h"

#include <zlib.h>

#include <algorithm>
#include <limits>

#include "shared/common/check.h"

namespace mbstream::mcap {

namespace {

template <typename T>
void PutLittleEndian(std::string& out, T value) {
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    out.push_back(static_cast<char>((static_cast<std::uint64_t>(value) >> (8 * i)) & 0xFF));
  }
}

void PutU8(std::string& out, std::uint8_t v) { out.push_back(static_cast<char>(v)); }
void PutU16(std::string& out, std::uint16_t v) { PutLittleEndian(out, v); }
void PutU32(std::string& out, std::uint32_t v) { PutLittleEndian(out, v); }
void PutU64(std::string& out, std::uint64_t v) { PutLittleEndian(out, v); }

std::uint32_t Length32(std::size_t size) {
  MBSTREAM_CHECK(size <= std::numeric_limits<std::uint32_t>::max());
  return static_cast<std::uint32_t>(size);
}

void PutString(std::string& out, std::string_view s) {
  PutU32(out, Length32(s.size()));
  out.append(s);
}

// Opens a record: opcode and a length to fill in by Close.
class RecordScope {
 public:
  RecordScope(std::string& out, Opcode opcode) : out_(out) {
    PutU8(out_, static_cast<std::uint8_t>(opcode));
    length_at_ = out_.size();
    PutU64(out_, 0);
  }
  ~RecordScope() {
    std::uint64_t length = out_.size() - length_at_ - 8;
    for (int i = 0; i < 8; ++i) {
      out_[length_at_ + i] = static_cast<char>((length >> (8 * i)) & 0xFF);
    }
  }
  RecordScope(const RecordScope&) = delete;
  RecordScope& operator=(const RecordScope&) = delete;

 private:
  std::string& out_;
  std::size_t length_at_ = 0;
};

// A Map or Array: uint32 byte length, then the entries `put` appends.
template <typename Put>
void PutSized(std::string& out, Put put) {
  const std::size_t length_at = out.size();
  PutU32(out, 0);
  put();
  const std::uint32_t length = Length32(out.size() - length_at - 4);
  for (int i = 0; i < 4; ++i) out[length_at + i] = static_cast<char>((length >> (8 * i)) & 0xFF);
}

}  // namespace

void AppendMagic(std::string& out) { out.append(kMagic); }

void Append(std::string& out, const Header& record) {
  RecordScope scope(out, Opcode::kHeader);
  PutString(out, record.profile);
  PutString(out, record.library);
}

void Append(std::string& out, const Schema& record) {
  RecordScope scope(out, Opcode::kSchema);
  PutU16(out, record.id);
  PutString(out, record.name);
  PutString(out, record.encoding);
  PutString(out, record.data);  // uint32 length prefixed bytes
}

void Append(std::string& out, const Channel& record) {
  RecordScope scope(out, Opcode::kChannel);
  PutU16(out, record.id);
  PutU16(out, record.schema_id);
  PutString(out, record.topic);
  PutString(out, record.message_encoding);
  PutSized(out, [&] {
    for (const auto& [key, value] : record.metadata) {
      PutString(out, key);
      PutString(out, value);
    }
  });
}

void Append(std::string& out, const Message& record) {
  RecordScope scope(out, Opcode::kMessage);
  PutU16(out, record.channel_id);
  PutU32(out, record.sequence);
  PutU64(out, record.log_time);
  PutU64(out, record.publish_time);
  out.append(record.data);  // the rest of the record
}

void Append(std::string& out, const Chunk& record) {
  RecordScope scope(out, Opcode::kChunk);
  PutU64(out, record.message_start_time);
  PutU64(out, record.message_end_time);
  PutU64(out, record.uncompressed_size);
  PutU32(out, record.uncompressed_crc);
  PutString(out, record.compression);
  PutU64(out, record.records.size());
  out.append(record.records);
}

void Append(std::string& out, const MessageIndex& record) {
  RecordScope scope(out, Opcode::kMessageIndex);
  PutU16(out, record.channel_id);
  PutSized(out, [&] {
    for (const auto& [log_time, offset] : record.records) {
      PutU64(out, log_time);
      PutU64(out, offset);
    }
  });
}

void Append(std::string& out, const ChunkIndex& record) {
  RecordScope scope(out, Opcode::kChunkIndex);
  PutU64(out, record.message_start_time);
  PutU64(out, record.message_end_time);
  PutU64(out, record.chunk_start_offset);
  PutU64(out, record.chunk_length);
  PutSized(out, [&] {
    for (const auto& [channel_id, offset] : record.message_index_offsets) {
      PutU16(out, channel_id);
      PutU64(out, offset);
    }
  });
  PutU64(out, record.message_index_length);
  PutString(out, record.compression);
  PutU64(out, record.compressed_size);
  PutU64(out, record.uncompressed_size);
}

void Append(std::string& out, const Statistics& record) {
  RecordScope scope(out, Opcode::kStatistics);
  PutU64(out, record.message_count);
  PutU16(out, record.schema_count);
  PutU32(out, record.channel_count);
  PutU32(out, record.attachment_count);
  PutU32(out, record.metadata_count);
  PutU32(out, record.chunk_count);
  PutU64(out, record.message_start_time);
  PutU64(out, record.message_end_time);
  PutSized(out, [&] {
    for (const auto& [channel_id, count] : record.channel_message_counts) {
      PutU16(out, channel_id);
      PutU64(out, count);
    }
  });
}

void Append(std::string& out, const DataEnd& record) {
  RecordScope scope(out, Opcode::kDataEnd);
  PutU32(out, record.data_section_crc);
}

void Append(std::string& out, const SummaryOffset& record) {
  RecordScope scope(out, Opcode::kSummaryOffset);
  PutU8(out, static_cast<std::uint8_t>(record.group_opcode));
  PutU64(out, record.group_start);
  PutU64(out, record.group_length);
}

void AppendFooterPrefix(std::string& out, const Footer& record) {
  PutU8(out, static_cast<std::uint8_t>(Opcode::kFooter));
  PutU64(out, 8 + 8 + 4);
  PutU64(out, record.summary_start);
  PutU64(out, record.summary_offset_start);
}

void Append(std::string& out, const Footer& record) {
  AppendFooterPrefix(out, record);
  PutU32(out, record.summary_crc);
}

std::uint32_t Crc32(std::string_view bytes, std::uint32_t crc) {
  // zlib's crc32 takes uInt lengths: feed large buffers in pieces.
  while (!bytes.empty()) {
    const std::size_t piece = std::min<std::size_t>(bytes.size(), 1u << 30);
    crc = static_cast<std::uint32_t>(
        ::crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(piece)));
    bytes.remove_prefix(piece);
  }
  return crc;
}

}  // namespace mbstream::mcap
