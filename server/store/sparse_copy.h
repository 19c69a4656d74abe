// Copies the first bytes of a file that may have holes (the frames file, frame_file.h) into a
// new file, holes kept as holes (SEEK_DATA / SEEK_HOLE), and makes the copy durable. For
// SqliteStore::Backup.
#pragma once

#include <cstdint>
#include <string>

namespace mbstream {

// Copies bytes [0, bytes) of `from` into `to` (created; it must not exist), whose size is then
// `bytes`, and fsyncs it. Returns the bytes of data copied (holes not counted). Throws
// InputError naming the file and the system's error (DiskFullError when the disk is full).
int64_t CopySparse(const std::string& from, const std::string& to, int64_t bytes);

// fsync of a file or directory by path; throws InputError naming it when that fails.
void SyncPath(const std::string& path);

}  // namespace mbstream
