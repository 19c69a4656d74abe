#include "server/mcap/mcap_writer.h"

#include <limits>

#include "shared/common/check.h"

namespace mbstream::mcap {

McapWriter::McapWriter(const std::string& path, McapWriterOptions options)
    : McapWriter(std::make_unique<McapFileSink>(path), std::move(options)) {}

McapWriter::McapWriter(std::unique_ptr<McapSink> sink, McapWriterOptions options)
    : sink_(std::move(sink)), options_(std::move(options)) {
  MBSTREAM_CHECK(sink_ != nullptr);
  scratch_.clear();
  AppendMagic(scratch_);
  Append(scratch_, Header{options_.profile, options_.library});
  Emit(scratch_, true);
}

void McapWriter::Emit(std::string_view bytes, bool data_section) {
  sink_->Write(bytes);
  if (data_section) data_crc_ = Crc32(bytes, data_crc_);
  offset_ += bytes.size();
}

std::uint16_t McapWriter::AddSchema(std::string name, std::string encoding, std::string data) {
  MBSTREAM_CHECK(schemas_.size() < std::numeric_limits<std::uint16_t>::max() - 1);
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
  schemas_.push_back(Schema{id, std::move(name), std::move(encoding), std::move(data)});
  // In the chunk too, so that a reader streaming the data section knows it before its messages.
  Append(chunk_records_, schemas_.back());
  return id;
}

std::uint16_t McapWriter::AddChannel(std::uint16_t schema_id, std::string topic,
                                     std::string message_encoding,
                                     std::vector<std::pair<std::string, std::string>> metadata) {
  MBSTREAM_CHECK(schema_id >= 1 && schema_id <= schemas_.size());
  MBSTREAM_CHECK(channels_.size() < std::numeric_limits<std::uint16_t>::max());
  const auto id = static_cast<std::uint16_t>(channels_.size());
  channels_.push_back(
      Channel{id, schema_id, std::move(topic), std::move(message_encoding), std::move(metadata)});
  sequences_.push_back(0);
  Append(chunk_records_, channels_.back());
  return id;
}

void McapWriter::Write(std::uint16_t channel_id, std::uint64_t log_time, std::string_view data) {
  MBSTREAM_CHECK(!closed_ && channel_id < channels_.size());
  if (!chunk_has_messages_) {
    chunk_start_time_ = log_time;
    chunk_end_time_ = log_time;
    chunk_has_messages_ = true;
  }
  chunk_start_time_ = std::min(chunk_start_time_, log_time);
  chunk_end_time_ = std::max(chunk_end_time_, log_time);
  MessageIndex& index = chunk_message_indexes_[channel_id];
  index.channel_id = channel_id;
  index.records.emplace_back(log_time, chunk_records_.size());
  Append(chunk_records_, Message{channel_id, sequences_[channel_id]++, log_time, log_time, data});

  if (statistics_.message_count == 0) {
    statistics_.message_start_time = log_time;
    statistics_.message_end_time = log_time;
  }
  ++statistics_.message_count;
  statistics_.message_start_time = std::min(statistics_.message_start_time, log_time);
  statistics_.message_end_time = std::max(statistics_.message_end_time, log_time);
  ++channel_counts_[channel_id];

  if (chunk_records_.size() >= options_.chunk_size) FlushChunk();
}

void McapWriter::FlushChunk() {
  if (chunk_records_.empty()) return;
  Compress(options_.compression, chunk_records_, compressed_);
  ChunkIndex index;
  index.message_start_time = chunk_has_messages_ ? chunk_start_time_ : 0;
  index.message_end_time = chunk_has_messages_ ? chunk_end_time_ : 0;
  index.chunk_start_offset = offset_;
  index.compression = CompressionName(options_.compression);
  index.compressed_size = compressed_.size();
  index.uncompressed_size = chunk_records_.size();

  scratch_.clear();
  Append(scratch_, Chunk{index.message_start_time, index.message_end_time, chunk_records_.size(),
                         Crc32(chunk_records_), index.compression, compressed_});
  index.chunk_length = scratch_.size();
  Emit(scratch_, true);

  // The chunk's MessageIndex records, one per channel, in channel order.
  const std::uint64_t indexes_start = offset_;
  for (const auto& [channel_id, message_index] : chunk_message_indexes_) {
    index.message_index_offsets.emplace_back(channel_id, offset_);
    scratch_.clear();
    Append(scratch_, message_index);
    Emit(scratch_, true);
  }
  index.message_index_length = offset_ - indexes_start;
  chunk_indexes_.push_back(std::move(index));

  chunk_records_.clear();
  chunk_message_indexes_.clear();
  chunk_has_messages_ = false;
}

void McapWriter::Close() {
  MBSTREAM_CHECK(!closed_);
  FlushChunk();
  scratch_.clear();
  Append(scratch_, DataEnd{data_crc_});
  Emit(scratch_, false);

  // The summary section, one group per record kind, each group's place kept for its
  // SummaryOffset record.
  const std::uint64_t summary_start = offset_;
  std::uint32_t summary_crc = 0;
  std::vector<SummaryOffset> offsets;
  auto group = [&](Opcode opcode, auto&& append_records) {
    scratch_.clear();
    append_records();
    if (scratch_.empty()) return;
    offsets.push_back(SummaryOffset{opcode, offset_, scratch_.size()});
    summary_crc = Crc32(scratch_, summary_crc);
    Emit(scratch_, false);
  };
  group(Opcode::kSchema, [&] {
    for (const Schema& schema : schemas_) Append(scratch_, schema);
  });
  group(Opcode::kChannel, [&] {
    for (const Channel& channel : channels_) Append(scratch_, channel);
  });
  statistics_.schema_count = static_cast<std::uint16_t>(schemas_.size());
  statistics_.channel_count = static_cast<std::uint32_t>(channels_.size());
  statistics_.chunk_count = static_cast<std::uint32_t>(chunk_indexes_.size());
  statistics_.channel_message_counts.assign(channel_counts_.begin(), channel_counts_.end());
  group(Opcode::kStatistics, [&] { Append(scratch_, statistics_); });
  group(Opcode::kChunkIndex, [&] {
    for (const ChunkIndex& index : chunk_indexes_) Append(scratch_, index);
  });

  const std::uint64_t summary_offset_start = offset_;
  scratch_.clear();
  for (const SummaryOffset& summary_offset : offsets) Append(scratch_, summary_offset);
  summary_crc = Crc32(scratch_, summary_crc);
  Emit(scratch_, false);

  Footer footer{summary_start, summary_offset_start, 0};
  scratch_.clear();
  AppendFooterPrefix(scratch_, footer);
  footer.summary_crc = Crc32(scratch_, summary_crc);
  scratch_.clear();
  Append(scratch_, footer);
  AppendMagic(scratch_);
  Emit(scratch_, false);

  sink_->Close();
  closed_ = true;
}

}  // namespace mbstream::mcap
