// The records of an MCAP file, named and laid out as the MCAP specification's sections say
// (mcap.dev/spec, major version 0): each Append* adds one record -- opcode (1 byte), content
// length (uint64) and content -- to `out`. Integers are little-endian; a String is a uint32
// byte length and the bytes; Bytes in a Chunk a uint64 length; a Map or Array a uint32 byte
// length and its entries.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mbstream::mcap {

enum class Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// Magic: the file's first and last 8 bytes (0x89 "MCAP" '0' "\r\n").
inline constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};

struct Header {
  std::string profile;  // "ros2": rosbag2's conventions
  std::string library;
};

struct Schema {
  std::uint16_t id = 0;  // 1.., 0 is reserved
  std::string name;      // "sensor_msgs/msg/JointState"
  std::string encoding;  // "ros2msg", "jsonschema"
  std::string data;      // the definition
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;  // "cdr", "json"
  std::vector<std::pair<std::string, std::string>> metadata;
};

struct Message {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;      // ns
  std::uint64_t publish_time = 0;  // ns
  std::string_view data;
};

struct Chunk {
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::uint64_t uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string compression;   // "", "zstd", "lz4"
  std::string_view records;  // compressed as `compression` says
};

struct MessageIndex {
  std::uint16_t channel_id = 0;
  // (log_time, offset of the Message record in the chunk's uncompressed records)
  std::vector<std::pair<std::uint64_t, std::uint64_t>> records;
};

struct ChunkIndex {
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::uint64_t chunk_start_offset = 0;  // the Chunk record's opcode, from the file's start
  std::uint64_t chunk_length = 0;        // the whole Chunk record
  std::vector<std::pair<std::uint16_t, std::uint64_t>> message_index_offsets;
  std::uint64_t message_index_length = 0;  // the MessageIndex records after the chunk
  std::string compression;
  std::uint64_t compressed_size = 0;
  std::uint64_t uncompressed_size = 0;
};

struct Statistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t attachment_count = 0;
  std::uint32_t metadata_count = 0;
  std::uint32_t chunk_count = 0;
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::vector<std::pair<std::uint16_t, std::uint64_t>> channel_message_counts;
};

struct DataEnd {
  std::uint32_t data_section_crc = 0;  // CRC-32 of every byte before this record
};

struct SummaryOffset {
  Opcode group_opcode = Opcode::kSchema;
  std::uint64_t group_start = 0;
  std::uint64_t group_length = 0;
};

struct Footer {
  std::uint64_t summary_start = 0;
  std::uint64_t summary_offset_start = 0;
  // CRC-32 from summary_start up to and including this record's summary_offset_start field.
  std::uint32_t summary_crc = 0;
};

void AppendMagic(std::string& out);
void Append(std::string& out, const Header& record);
void Append(std::string& out, const Schema& record);
void Append(std::string& out, const Channel& record);
void Append(std::string& out, const Message& record);
void Append(std::string& out, const Chunk& record);
void Append(std::string& out, const MessageIndex& record);
void Append(std::string& out, const ChunkIndex& record);
void Append(std::string& out, const Statistics& record);
void Append(std::string& out, const DataEnd& record);
void Append(std::string& out, const SummaryOffset& record);
// The Footer without its summary_crc: the bytes the summary CRC covers last.
void AppendFooterPrefix(std::string& out, const Footer& record);
void Append(std::string& out, const Footer& record);

// CRC-32 (ISO-HDLC, zlib's) of `bytes`, continuing from `crc` (0 to start).
std::uint32_t Crc32(std::string_view bytes, std::uint32_t crc = 0);

}  // namespace mbstream::mcap
