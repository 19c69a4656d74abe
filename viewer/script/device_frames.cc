#include "viewer/script/device_frames.h"

#include <charconv>

namespace mbstream::scene_script {

bool SplitLinkName(std::string_view name, std::string* prefix, int* k) {
  const size_t hash = name.rfind('#');
  if (hash == std::string_view::npos || hash + 1 >= name.size()) return false;
  const std::string_view digits = name.substr(hash + 1);
  int value = 0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec != std::errc() || ptr != digits.data() + digits.size() || value < 0) return false;
  *prefix = std::string(name.substr(0, hash));
  *k = value;
  return true;
}

std::optional<int> DeviceFrameNumber(const DeviceCommand& device, std::string_view name) {
  if (name == device.name) return 0;
  std::string prefix;
  int k = 0;
  if (!SplitLinkName(name, &prefix, &k) || prefix != device.name) return std::nullopt;
  if (k > static_cast<int>(device.joints.size())) return std::nullopt;
  return k;
}

std::string DeviceFrameName(const DeviceCommand& device, int frame) {
  return frame == 0 ? device.name : device.name + "#" + std::to_string(frame);
}

std::vector<std::string> DeviceFrameNames(const DeviceCommand& device) {
  std::vector<std::string> names;
  for (int k = 0; k <= static_cast<int>(device.joints.size()); ++k) {
    names.push_back(DeviceFrameName(device, k));
  }
  return names;
}

}  // namespace mbstream::scene_script
