#include "server/mcap/mcap_compression.h"

#include <lz4frame.h>
#include <zstd.h>

#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream::mcap {

const char* CompressionName(Compression compression) {
  switch (compression) {
    case Compression::kNone:
      return "";
    case Compression::kZstd:
      return "zstd";
    case Compression::kLz4:
      return "lz4";
  }
  return "";
}

Compression ParseCompression(std::string_view name) {
  if (name == "none") return Compression::kNone;
  if (name == "zstd") return Compression::kZstd;
  if (name == "lz4") return Compression::kLz4;
  throw InputError(FormatString("unknown MCAP compression \"%s\": use zstd, lz4 or none",
                                std::string(name).c_str()));
}

void Compress(Compression compression, std::string_view in, std::string& out) {
  switch (compression) {
    case Compression::kNone:
      out.assign(in);
      return;
    case Compression::kZstd: {
      out.resize(ZSTD_compressBound(in.size()));
      const std::size_t size = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), 3);
      if (ZSTD_isError(size)) {
        throw InternalError(FormatString("zstd compression failed: %s", ZSTD_getErrorName(size)));
      }
      out.resize(size);
      return;
    }
    case Compression::kLz4: {
      LZ4F_preferences_t preferences = LZ4F_INIT_PREFERENCES;
      preferences.frameInfo.contentSize = in.size();
      out.resize(LZ4F_compressFrameBound(in.size(), &preferences));
      const std::size_t size =
          LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), &preferences);
      if (LZ4F_isError(size)) {
        throw InternalError(FormatString("lz4 compression failed: %s", LZ4F_getErrorName(size)));
      }
      out.resize(size);
      return;
    }
  }
}

}  // namespace mbstream::mcap
