// Writes one MCAP file as messages come: chunked (a chunk holds about `chunk_size` bytes of
// records before it is compressed and written), each chunk followed by its MessageIndex
// records, then DataEnd with the data section's CRC, the summary section (Schema, Channel,
// Statistics, ChunkIndex records), the SummaryOffset section and the Footer with the
// summary's CRC. Memory holds one chunk and one ChunkIndex per chunk written, never the
// messages of earlier chunks. The bytes go to a McapSink front to back (a file written under a
// temporary name and renamed by Close, so a failed export leaves no half-written file, or a
// stream).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "server/mcap/mcap_compression.h"
#include "server/mcap/mcap_records.h"
#include "server/mcap/mcap_sink.h"

namespace mbstream::mcap {

struct McapWriterOptions {
  Compression compression = Compression::kZstd;
  std::size_t chunk_size = 1 << 20;  // bytes of uncompressed records per chunk
  std::string profile = "ros2";
  std::string library = "mbstream";
};

class McapWriter {
 public:
  // Opens `path`'s temporary file (McapFileSink); throws InputError naming it when it cannot.
  McapWriter(const std::string& path, McapWriterOptions options);
  // Writes into `sink` (not null).
  McapWriter(std::unique_ptr<McapSink> sink, McapWriterOptions options);
  // Without Close: the sink is dropped unclosed (a file sink removes its temporary file).
  ~McapWriter() = default;
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Returns the schema's id (1, 2, ...).
  std::uint16_t AddSchema(std::string name, std::string encoding, std::string data);
  // Returns the channel's id (0, 1, ...).
  std::uint16_t AddChannel(std::uint16_t schema_id, std::string topic, std::string message_encoding,
                           std::vector<std::pair<std::string, std::string>> metadata = {});
  // One message; log_time and publish_time in ns.
  void Write(std::uint16_t channel_id, std::uint64_t log_time, std::string_view data);
  // Writes the last chunk, the summary and the footer and closes the sink (a file is renamed
  // into place). Throws the sink's error when it cannot be written (a full disk).
  void Close();

  std::uint64_t bytes_written() const { return offset_; }
  std::uint32_t chunks_written() const { return static_cast<std::uint32_t>(chunk_indexes_.size()); }

 private:
  void Emit(std::string_view bytes, bool data_section);
  void FlushChunk();

  std::unique_ptr<McapSink> sink_;
  McapWriterOptions options_;
  std::uint64_t offset_ = 0;
  std::uint32_t data_crc_ = 0;

  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;
  std::vector<std::uint32_t> sequences_;  // per channel

  // The open chunk: its records and, per channel, its message index.
  std::string chunk_records_;
  std::map<std::uint16_t, MessageIndex> chunk_message_indexes_;
  std::uint64_t chunk_start_time_ = 0;
  std::uint64_t chunk_end_time_ = 0;
  bool chunk_has_messages_ = false;
  std::string compressed_;
  std::string scratch_;

  std::vector<ChunkIndex> chunk_indexes_;
  Statistics statistics_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  bool closed_ = false;
};

}  // namespace mbstream::mcap
