// OMG CDR as ROS 2 writes its messages (XCDR1, little-endian, "plain CDR"): a 4-byte
// encapsulation header (0x00 0x01: CDR_LE, then two option bytes 0), then the fields, each
// primitive aligned to its own size counted from the end of that header. Strings are a
// uint32 length including the terminating NUL, the bytes and the NUL; a sequence is a uint32
// element count and its elements.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace mbstream::mcap {

class CdrWriter {
 public:
  // Starts a message in `out` (cleared; its capacity is kept, so a reused buffer allocates
  // nothing once it is large enough).
  explicit CdrWriter(std::string& out) : out_(out) {
    out_.clear();
    out_.append("\x00\x01\x00\x00", 4);
  }

  void Int32(std::int32_t value) { Put(value); }
  void UInt32(std::uint32_t value) { Put(value); }
  void Float64(double value) { Put(value); }
  void String(std::string_view text) {
    UInt32(static_cast<std::uint32_t>(text.size() + 1));
    out_.append(text);
    out_.push_back('\0');
  }
  // sequence<double>: the count, then the values (aligned to 8 only when there are any).
  void Float64Sequence(const double* values, std::size_t count) {
    UInt32(static_cast<std::uint32_t>(count));
    for (std::size_t i = 0; i < count; ++i) Float64(values[i]);
  }

 private:
  template <typename T>
  void Put(T value) {
    static_assert(std::endian::native == std::endian::little, "CDR_LE is written as in memory");
    const std::size_t payload = out_.size() - 4;
    out_.append((sizeof(T) - payload % sizeof(T)) % sizeof(T), '\0');
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out_.append(bytes, sizeof(T));
  }

  std::string& out_;
};

}  // namespace mbstream::mcap
