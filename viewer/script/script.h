// A translated scene script: its commands grouped by kind, names resolved, STL files found.
// Only a script that translated without errors is complete and consistent.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "viewer/script/commands.h"

namespace mbstream::scene_script {

struct Script {
  std::optional<DeviceCommand> device;
  std::vector<PartCommand> parts;      // in script order
  std::vector<SetCommand> sets;        // in script order
  std::vector<RenderCommand> renders;  // in script order
  std::vector<ProbeCommand> probes;    // in script order

  const PartCommand* FindPart(std::string_view name) const;
  const SetCommand* FindSet(std::string_view name) const;
  // The last Render of `name`, if any.
  const RenderCommand* FindRender(std::string_view name) const;
};

}  // namespace mbstream::scene_script
