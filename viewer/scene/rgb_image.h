// A captured frame: 8-bit RGB, rows from the top.
#pragma once

#include <cstdint>
#include <vector>

namespace mbstream::viewer {

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3

  const std::uint8_t* At(int x, int y) const { return &rgb[(size_t(y) * width + x) * 3]; }
};

}  // namespace mbstream::viewer
