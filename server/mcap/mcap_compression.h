// A chunk's compression, as MCAP names it: "" (none), "zstd" (Zstandard), "lz4" (an LZ4 frame).
#pragma once

#include <string>
#include <string_view>

namespace mbstream::mcap {

enum class Compression { kNone, kZstd, kLz4 };

// "", "zstd", "lz4": the Chunk record's compression field.
const char* CompressionName(Compression compression);

// "none", "zstd" or "lz4" (a command line's spelling); throws InputError listing them.
Compression ParseCompression(std::string_view name);

// Replaces `out` with `in` compressed (`in` itself for kNone).
void Compress(Compression compression, std::string_view in, std::string& out);

}  // namespace mbstream::mcap
