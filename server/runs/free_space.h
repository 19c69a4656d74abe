// The free space a server needs on its data directory's disk before it starts a run
// (--min-free-mb): below it new runs are refused with RESOURCE_EXHAUSTED, not failed later by
// a full disk. SQLite store only: a PostgreSQL store's disk is the database server's.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace mbstream {

// Bytes an unprivileged writer may still use on the file system holding `path`
// (statvfs: f_bavail * f_frsize); nullopt when statvfs fails.
std::optional<int64_t> FreeBytesAt(const std::string& path);

// Where the free bytes come from (FreeBytesAt of the data directory; tests inject their
// own). nullopt: unknown, and the check lets the run start.
using FreeSpaceSource = std::function<std::optional<int64_t>()>;

// Throws RequestError(kResourceExhausted) when `source` says fewer than `min_free_bytes`
// are free on the disk of `data_dir`; the message says what to do. Nothing when
// `min_free_bytes` <= 0 or `source` is empty or answers nullopt.
void CheckFreeSpace(const FreeSpaceSource& source, int64_t min_free_bytes,
                    const std::string& data_dir);

}  // namespace mbstream
