// The MCAP records' bytes as the specification lays them out, a tiny file walked record by
// record with its CRCs, and the CDR of a JointState: known bytes written by hand.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "server/mcap/mcap_records.h"
#include "server/mcap/mcap_writer.h"
#include "server/mcap/ros_messages.h"
#include "shared/common/check.h"

namespace mbstream::mcap {
namespace {

std::string Bytes(std::initializer_list<int> bytes) {
  std::string out;
  for (int b : bytes) out.push_back(static_cast<char>(b));
  return out;
}

std::uint64_t U64At(const std::string& s, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s[at + i]);
  return v;
}

std::uint32_t U32At(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s[at + i]);
  return v;
}

TEST(McapRecordsTest, HeaderIsOpcodeLengthAndTwoStrings) {
  std::string out;
  Append(out, Header{"ros2", "x"});
  EXPECT_EQ(
      out, Bytes({0x01, 13, 0, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 'r', 'o', 's', '2', 1, 0, 0, 0, 'x'}));
}

TEST(McapRecordsTest, MessageDataIsTheRestOfTheRecord) {
  std::string out;
  Append(out, Message{1, 2, 3, 4, "ab"});
  EXPECT_EQ(out, Bytes({0x05, 24, 0, 0, 0, 0, 0, 0, 0, 1, 0, 2, 0, 0, 0,   3,  0,
                        0,    0,  0, 0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 'a', 'b'}));
}

TEST(McapRecordsTest, ChannelMetadataIsAMapWithItsByteLength) {
  std::string out;
  Append(out, Channel{7, 1, "/t", "cdr", {{"k", "v"}}});
  EXPECT_EQ(out,
            Bytes({0x04, 31, 0, 0,   0,   0,   0,  0, 0, 7, 0, 1, 0, 2, 0,   0, 0, '/', 't', 3,
                   0,    0,  0, 'c', 'd', 'r', 10, 0, 0, 0, 1, 0, 0, 0, 'k', 1, 0, 0,   0,   'v'}));
}

TEST(McapRecordsTest, FooterAndSummaryOffset) {
  std::string out;
  Append(out, Footer{0x10, 0x20, 0x01020304});
  EXPECT_EQ(out, Bytes({0x02, 20, 0,    0, 0, 0, 0, 0, 0, 0x10, 0, 0, 0, 0, 0,
                        0,    0,  0x20, 0, 0, 0, 0, 0, 0, 0,    4, 3, 2, 1}));
  out.clear();
  Append(out, SummaryOffset{Opcode::kChunkIndex, 5, 6});
  EXPECT_EQ(out, Bytes({0x0E, 17, 0, 0, 0, 0, 0, 0, 0, 0x08, 5, 0, 0,
                        0,    0,  0, 0, 0, 6, 0, 0, 0, 0,    0, 0, 0}));
}

TEST(McapRecordsTest, Crc32IsZlibs) {
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(Crc32("6789", Crc32("12345")), 0xCBF43926u);
}

TEST(McapRecordsTest, JointStateCdrAlignsFromThePayloadStart) {
  std::string out;
  const double position = 1.0, velocity = 2.0;
  EncodeJointState(out, RosTime{1, 2}, {"a"}, &position, &velocity, 1, nullptr, 0);
  EXPECT_EQ(out,
            Bytes({0x00, 0x01, 0x00, 0x00,                                     // CDR_LE
                   1,    0,    0,    0,    2, 0, 0, 0,                         // stamp
                   1,    0,    0,    0,    0,                                  // frame_id ""
                   0,    0,    0,                                              // pad to 4
                   1,    0,    0,    0,    2, 0, 0, 0,    'a', 0,              // name ["a"]
                   0,    0,                                                    // pad to 4
                   1,    0,    0,    0,    0, 0, 0, 0,    0,   0, 0xF0, 0x3F,  // position [1.0]
                   1,    0,    0,    0,    0, 0, 0, 0,                         // count, pad to 8
                   0,    0,    0,    0,    0, 0, 0, 0x40,                      // velocity [2.0]
                   0,    0,    0,    0}));                                     // effort []
}

TEST(McapRecordsTest, RosTimeSplitsNanoseconds) {
  const RosTime t = RosTime::FromNanoseconds(1764158400'123456789ull);
  EXPECT_EQ(t.sec, 1764158400);
  EXPECT_EQ(t.nanosec, 123456789u);
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A file of one schema, one channel and two messages, uncompressed: every record in its place
// and every CRC what a reader recomputes.
TEST(McapWriterTest, TinyFileHasEverySectionAndItsCrcs) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("mbstream_mcap_tiny-" + std::to_string(getpid()) + ".mcap");
  {
    McapWriter writer(path.string(), {.compression = Compression::kNone, .library = "test"});
    const std::uint16_t schema = writer.AddSchema("s", "jsonschema", "{}");
    const std::uint16_t channel = writer.AddChannel(schema, "/c", "json");
    writer.Write(channel, 100, "{\"a\":1}");
    writer.Write(channel, 200, "{\"a\":2}");
    writer.Close();
  }
  const std::string file = ReadFile(path);
  std::filesystem::remove(path);
  ASSERT_GT(file.size(), 16u);
  EXPECT_EQ(file.substr(0, 8), std::string(kMagic));
  EXPECT_EQ(file.substr(file.size() - 8), std::string(kMagic));

  // Walk the records from the header to the footer.
  std::vector<int> opcodes;
  std::size_t at = 8, data_end_at = 0, chunk_at = 0;
  while (at < file.size() - 8) {
    const int opcode = static_cast<unsigned char>(file[at]);
    opcodes.push_back(opcode);
    if (opcode == 0x0F) data_end_at = at;
    if (opcode == 0x06) chunk_at = at;
    at += 9 + U64At(file, at + 1);
  }
  EXPECT_EQ(at, file.size() - 8);
  // Header, Chunk, MessageIndex, DataEnd, Schema, Channel, Statistics, ChunkIndex,
  // 4 x SummaryOffset, Footer.
  EXPECT_EQ(opcodes, (std::vector<int>{0x01, 0x06, 0x07, 0x0F, 0x03, 0x04, 0x0B, 0x08, 0x0E, 0x0E,
                                       0x0E, 0x0E, 0x02}));

  // The chunk: times, sizes, the CRC of its records.
  const std::uint64_t start = U64At(file, chunk_at + 9), end = U64At(file, chunk_at + 17);
  EXPECT_EQ(start, 100u);
  EXPECT_EQ(end, 200u);
  const std::uint64_t uncompressed_size = U64At(file, chunk_at + 25);
  const std::uint32_t uncompressed_crc = U32At(file, chunk_at + 33);
  ASSERT_EQ(U32At(file, chunk_at + 37), 0u);  // compression ""
  ASSERT_EQ(U64At(file, chunk_at + 41), uncompressed_size);
  const std::string records = file.substr(chunk_at + 49, uncompressed_size);
  EXPECT_EQ(Crc32(records), uncompressed_crc);
  EXPECT_EQ(static_cast<unsigned char>(records[0]), 0x03);  // the schema before the channel
  EXPECT_NE(records.find("{\"a\":2}"), std::string::npos);

  // DataEnd's CRC covers every byte before it; the footer's the summary up to its own CRC.
  EXPECT_EQ(U32At(file, data_end_at + 9), Crc32(std::string_view(file).substr(0, data_end_at)));
  const std::size_t footer_at = file.size() - 8 - 29;
  const std::uint64_t summary_start = U64At(file, footer_at + 9);
  EXPECT_EQ(summary_start, data_end_at + 13);
  EXPECT_EQ(U32At(file, footer_at + 25),
            Crc32(std::string_view(file).substr(summary_start, footer_at + 25 - summary_start)));
}

TEST(McapWriterTest, UnwritableFolderIsNamed) {
  try {
    McapWriter writer("/nonexistent-folder/run.mcap", {});
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent-folder/run.mcap.tmp"), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("check that its folder exists"), std::string::npos);
  }
}

TEST(McapCompressionTest, NamesAndAnUnknownOne) {
  EXPECT_EQ(ParseCompression("zstd"), Compression::kZstd);
  EXPECT_EQ(ParseCompression("lz4"), Compression::kLz4);
  EXPECT_EQ(ParseCompression("none"), Compression::kNone);
  EXPECT_STREQ(CompressionName(Compression::kNone), "");
  try {
    ParseCompression("gzip");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "unknown MCAP compression \"gzip\": use zstd, lz4 or none");
  }
}

}  // namespace
}  // namespace mbstream::mcap
