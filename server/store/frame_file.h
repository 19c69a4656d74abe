// The SQLite store's frames, outside the database: one append-only file
// (<data dir>/mbstream.frames) holding each chunk blob (frame_chunks.h) where its row in
// frame_chunks points (offset, bytes, CRC-32C). A result's 84 KB then costs one write() instead
// of some 50 WAL page writes and the checkpoint's copy of each (docs/performance.md, "Many
// runs at once").
//
// Crash story: a chunk is appended before the transaction that stores its row commits, so a
// committed row never points past what this process wrote; a process that dies between the
// two leaves unreferenced bytes at the end, which the next append simply follows. What the
// operating system had not yet written when the machine stopped (SQLite's WAL, written without
// fsync per commit as the store's synchronous=NORMAL allows, may have reached the disk before
// this file did) is caught at read by the length and checksum: the chunk is reported damaged,
// never served. Sync() (before each checkpoint) bounds how far back that can reach.
//
// Space comes back without moving a byte: the chunks of a deleted run are released (Release:
// a hole punched in the file, its size kept) once the transaction that deleted their rows has
// committed, and at open the store releases every gap between referenced chunks (those of a
// run stored again, of a delete a crash interrupted before its release). Offsets never change,
// so a kill -9 at any point leaves every referenced chunk where its row says, its CRC valid;
// it can only leave unreferenced bytes allocated until the next open.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace mbstream {

// Where a chunk's bytes are in the file.
struct FrameExtent {
  int64_t offset = 0;
  int64_t bytes = 0;
  uint32_t crc32c = 0;  // CRC-32C (Castagnoli) of the bytes
};

class FrameFile {
 public:
  // Opens or creates `path`; appends go to its end. Throws InputError naming the path when it
  // cannot be opened for reading and writing.
  explicit FrameFile(std::string path);
  ~FrameFile();
  FrameFile(const FrameFile&) = delete;
  FrameFile& operator=(const FrameFile&) = delete;

  // Writes `data` at the end of the file in one piece (O_APPEND: another FrameFile or process
  // appending to the same file meanwhile cannot interleave with it). Not thread-safe against
  // another Append on this object (the store's mutex serialises them); Read may run alongside.
  // Throws InputError (naming the file and the system's error) when the write fails or is
  // short; its bytes are then referenced by nothing.
  FrameExtent Append(std::string_view data);
  // Reads the extent into `out`; false when the file is too short or the bytes do not match
  // their checksum.
  bool Read(const FrameExtent& extent, std::string& out) const;
  // Makes every append so far durable (fdatasync). Throws InputError when that fails.
  void Sync() const;

  // Gives the disk blocks of bytes [offset, offset + bytes) back to the file system (a hole:
  // they read as zeros; the file's size stays). Only bytes no row refers to. False when the
  // file system cannot punch holes or the call failed (the bytes then stay allocated).
  bool Release(int64_t offset, int64_t bytes);

  const std::string& path() const { return path_; }
  int64_t end() const;              // the file's size
  int64_t allocated_bytes() const;  // what it occupies on the disk

 private:
  std::string path_;
  int fd_ = -1;
};

// CRC-32C of `data` (the SSE4.2 instruction where the processor has it).
uint32_t Crc32c(std::string_view data);

}  // namespace mbstream
