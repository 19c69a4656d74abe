// FrameFile: appends found again where they were written, across a reopen; a file cut short
// or a changed byte is refused, never read as frames.
#include "server/store/frame_file.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "server/store/disk_full_error.h"
#include "shared/common/check.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using testing::TempDirectory;

TEST(FrameFileTest, Crc32cMatchesTheCastagnoliCheckValues) {
  EXPECT_EQ(Crc32c(""), 0u);
  EXPECT_EQ(Crc32c("123456789"), 0xe3069283u);            // the standard check value (RFC 3720)
  EXPECT_EQ(Crc32c(std::string(32, '\0')), 0x8a9136aau);  // RFC 3720's 32 zero bytes
  EXPECT_EQ(Crc32c(std::string(32, '\xff')), 0x62a8ab43u);
  std::string ascending;
  for (int i = 0; i < 32; ++i) ascending += static_cast<char>(i);
  EXPECT_EQ(Crc32c(ascending), 0x46dd794eu);
}

TEST(FrameFileTest, AppendsReadBackAcrossAReopenAndDamageIsRefused) {
  TempDirectory temp;
  std::filesystem::create_directories(temp.path());
  const std::string path = (temp.path() / "frames").string();
  FrameExtent a, b, c;
  {
    FrameFile file(path);
    EXPECT_EQ(file.end(), 0);
    a = file.Append("first chunk");
    b = file.Append(std::string(100000, 'x'));
    EXPECT_EQ(b.offset, a.bytes);
    file.Sync();
  }
  FrameFile file(path);
  EXPECT_EQ(file.end(), a.bytes + b.bytes);
  c = file.Append("after the reopen");
  EXPECT_EQ(c.offset, a.bytes + b.bytes);
  std::string out;
  ASSERT_TRUE(file.Read(a, out));
  EXPECT_EQ(out, "first chunk");
  ASSERT_TRUE(file.Read(b, out));
  EXPECT_EQ(out, std::string(100000, 'x'));
  ASSERT_TRUE(file.Read(c, out));
  EXPECT_EQ(out, "after the reopen");

  FrameExtent wrong = a;
  wrong.crc32c ^= 1;
  EXPECT_FALSE(file.Read(wrong, out));
  FrameExtent past = c;
  past.bytes += 1;  // beyond the end of the file
  EXPECT_FALSE(file.Read(past, out));
  {
    std::fstream raw(path, std::ios::in | std::ios::out | std::ios::binary);
    raw.seekp(3);
    raw.put('F');  // "fiRst" -> "fiFst"
  }
  EXPECT_FALSE(file.Read(a, out));
  EXPECT_TRUE(file.Read(b, out));
}

// Two writers of one file (two stores on one data directory, or a test's second one): each
// append lands whole where its extent says, none overwrites the other's.
TEST(FrameFileTest, TwoWritersOfOneFileNeverOverwriteEachOther) {
  TempDirectory temp;
  std::filesystem::create_directories(temp.path());
  const std::string path = (temp.path() / "frames").string();
  FrameFile one(path), two(path);
  std::vector<std::pair<FrameExtent, std::string>> written;
  for (int i = 0; i < 6; ++i) {
    const std::string data = std::string(1000 + i, static_cast<char>('a' + i));
    written.emplace_back((i % 2 == 0 ? one : two).Append(data), data);
  }
  EXPECT_EQ(one.end(), two.end());
  int64_t total = 0;
  for (const auto& [extent, data] : written) {
    std::string out;
    ASSERT_TRUE(one.Read(extent, out));
    EXPECT_EQ(out, data);
    EXPECT_EQ(extent.offset, total);
    total += extent.bytes;
  }
  EXPECT_EQ(one.end(), total);
}

TEST(FrameFileTest, AFileThatCannotBeOpenedIsAnInputErrorNamingIt) {
  TempDirectory temp;
  const std::string path = (temp.path() / "no-such-folder" / "frames").string();
  try {
    FrameFile file(path);
    FAIL() << "opened " << path;
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
}

// /dev/full answers every write with ENOSPC, as a full disk does: the append is refused with
// a DiskFullError (RESOURCE_EXHAUSTED on the wire) naming the file and the full disk.
TEST(FrameFileTest, AWriteToAFullDiskIsADiskFullErrorNamingIt) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  FrameFile file("/dev/full");
  try {
    file.Append("some frames");
    FAIL() << "a write to /dev/full succeeded";
  } catch (const DiskFullError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("/dev/full"), std::string::npos) << message;
    EXPECT_NE(message.find("disk holding the data directory is full"), std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace mbstream
