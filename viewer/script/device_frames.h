// Names of a device's frames: `NAME` (or `NAME#0`) is the base, `NAME#k` is link k.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "viewer/script/commands.h"

namespace mbstream::scene_script {

// Splits "PREFIX#K" (K a whole number). False for names without a numeric '#' suffix.
bool SplitLinkName(std::string_view name, std::string* prefix, int* k);

// The frame number of `name` in `device` (0 = base, 1..n = links), or nullopt.
std::optional<int> DeviceFrameNumber(const DeviceCommand& device, std::string_view name);

// "NAME" for 0, "NAME#k" otherwise.
std::string DeviceFrameName(const DeviceCommand& device, int frame);

// Every frame name: NAME, NAME#1 .. NAME#n.
std::vector<std::string> DeviceFrameNames(const DeviceCommand& device);

}  // namespace mbstream::scene_script
