#include "viewer/script/resolver.h"

#include <map>
#include <string>

#include "viewer/script/device_frames.h"
#include "viewer/script/name_suggestion.h"
#include "viewer/script/polyprism_outline.h"
#include "viewer/script/token_stream.h"

namespace mbstream::scene_script {

namespace {

enum class NameKind { kPart, kAssembly, kLink };

struct Definition {
  NameKind kind;
  SourcePosition position;
};

std::string Line(SourcePosition p) { return "line " + std::to_string(p.line); }

// Walks the commands in order; a name is usable only after its definition.
class Resolver {
 public:
  Resolver(const TranslateOptions& options, Diagnostics* diagnostics)
      : options_(options), diagnostics_(diagnostics) {}

  // Every name any command defines, with the first place it is defined: to tell "defined
  // later" from "undefined".
  void CollectLaterDefinitions(const std::vector<Command>& commands) {
    for (const Command& command : commands) {
      if (const auto* part = std::get_if<PartCommand>(&command)) {
        all_definitions_.emplace(part->name, part->name_position);
      } else if (const auto* set = std::get_if<SetCommand>(&command)) {
        all_definitions_.emplace(set->name, set->name_position);
      }
    }
  }

  void Resolve(DeviceCommand& device) {
    if (script_.device) {
      Error(device.position, "a script describes one Device; '" + script_.device->name +
                                 "' is already defined at " + Line(script_.device->position) +
                                 "; describe '" + device.name + "' in a script of its own");
      return;
    }
    script_.device = std::move(device);
  }

  void Resolve(PartCommand& part) {
    if (!DefineName(part.name, part.name_position, NameKind::kPart, part.keyword)) return;
    if (auto* stl = std::get_if<StlShape>(&part.shape)) {
      ResolveStl(part, stl);
    } else if (const auto* prism = std::get_if<PolyprismShape>(&part.shape)) {
      PolyprismOutline(*prism, diagnostics_);
    }
    script_.parts.push_back(std::move(part));
  }

  void Resolve(SetCommand& set) {
    const bool link = script_.device && DeviceFrameNumber(*script_.device, set.name);
    if (!link) CheckNotALinkName(set.name, set.name_position);
    if (!DefineName(set.name, set.name_position, link ? NameKind::kLink : NameKind::kAssembly,
                    "Set")) {
      return;
    }
    for (const Component& component : set.components) {
      const auto it = defined_.find(component.name);
      if (it == defined_.end()) {
        Error(component.position, "undefined component '" + component.name + "' in Set '" +
                                      set.name + "'" + Suggest(component.name, false) + "; " +
                                      WhatToDo(component.name));
      } else if (it->second.kind == NameKind::kLink) {
        Error(component.position, "'" + component.name +
                                      "' is a device link and cannot be a component; add its "
                                      "parts to Set '" +
                                      set.name + "' instead");
      }
    }
    script_.sets.push_back(std::move(set));
  }

  void Resolve(RenderCommand& render) {
    if (!defined_.contains(render.target)) {
      Error(render.target_position, "undefined name '" + render.target + "' in Render" +
                                        Suggest(render.target, true) + "; " +
                                        WhatToDo(render.target));
      return;
    }
    script_.renders.push_back(std::move(render));
  }

  void Resolve(ProbeCommand& probe) {
    for (const ProbeCommand& other : script_.probes) {
      if (other.name == probe.name) {
        Error(probe.name_position, "probe '" + probe.name + "' is already defined at " +
                                       Line(other.name_position) + "; give it another name");
        return;
      }
    }
    const bool frame_ok = CheckFrame(probe, probe.frame_in, probe.frame_in_position, "in");
    const bool refer_ok = CheckFrame(probe, probe.refer, probe.refer_position, "to refer to");
    if (frame_ok && refer_ok) script_.probes.push_back(std::move(probe));
  }

  Script Take() { return std::move(script_); }

 private:
  void Error(SourcePosition position, std::string message) {
    diagnostics_->Error(position, std::move(message));
  }

  bool DefineName(const std::string& name, SourcePosition position, NameKind kind,
                  const std::string& command) {
    if (const auto it = defined_.find(name); it != defined_.end()) {
      if (kind == NameKind::kLink) {
        Error(position, "link '" + name + "' is already built by the Set at " +
                            Line(it->second.position) +
                            "; add all the link's components in one Set");
      } else {
        Error(position, "'" + name + "' is already defined at " + Line(it->second.position) +
                            "; give this " + command + " another name");
      }
      return false;
    }
    if (kind == NameKind::kPart && script_.device &&
        (name == script_.device->name || DeviceFrameNumber(*script_.device, name))) {
      Error(position, "'" + name + "' names the device or one of its links; a " + command +
                          " cannot take it: give the part another name and attach it with Set " +
                          name + " add ...");
      return false;
    }
    if (kind == NameKind::kPart) CheckNotALinkName(name, position);
    defined_[name] = {kind, position};
    return true;
  }

  // "X#k" where X is the device but k is out of range, or X is no device defined above.
  void CheckNotALinkName(const std::string& name, SourcePosition position) {
    std::string prefix;
    int k = 0;
    if (!SplitLinkName(name, &prefix, &k)) return;
    if (script_.device && prefix == script_.device->name) {
      Error(position, "'" + name + "': device '" + prefix + "' has links " + prefix + "#1.." +
                          prefix + "#" + std::to_string(script_.device->joints.size()) + " (and " +
                          prefix + " for its base); use one of them");
    }
  }

  void ResolveStl(const PartCommand& part, StlShape* stl) {
    std::optional<std::filesystem::path> path;
    if (options_.assets) path = options_.assets->Find(stl->file_name);
    const std::string where =
        options_.assets ? options_.assets->Describe() : "no asset directory given";
    if (!path) {
      Error(part.name_position, "Part '" + part.name + "': STL file '" + stl->file_name +
                                    ".stl' not found (" + where + "); " +
                                    options_.missing_asset_advice);
      return;
    }
    if (const auto problem = StlFileProblem(*path)) {
      Error(part.name_position, "Part '" + part.name + "': STL file '" + path->string() + "' " +
                                    *problem + "; replace it with a valid STL file");
      return;
    }
    stl->resolved_path = *path;
  }

  std::string Suggest(const std::string& name, bool include_links) const {
    std::vector<std::string> candidates;
    for (const auto& [defined, definition] : defined_) {
      if (include_links || definition.kind != NameKind::kLink) candidates.push_back(defined);
    }
    return DidYouMean(name, candidates);
  }

  std::string WhatToDo(const std::string& name) const {
    if (const auto it = all_definitions_.find(name); it != all_definitions_.end()) {
      return "it is defined later, at " + Line(it->second) +
             "; move its definition above this line";
    }
    return "define it with Set or a part command (Cylinder, Cone, Cube, Sphere, Polyprism, "
           "Module, Part) above this line";
  }

  bool CheckFrame(const ProbeCommand& probe, const std::string& frame, SourcePosition position,
                  std::string_view role) {
    if (EqualsIgnoreCase(frame, "World")) return true;
    if (script_.device && DeviceFrameNumber(*script_.device, frame)) return true;
    std::vector<std::string> names{"World"};
    std::string valid = "World";
    if (script_.device) {
      const std::vector<std::string> frames = DeviceFrameNames(*script_.device);
      names.insert(names.end(), frames.begin(), frames.end());
      valid += ", " + script_.device->name;
      if (!script_.device->joints.empty()) {
        valid += " or " + script_.device->name + "#1.." + script_.device->name + "#" +
                 std::to_string(script_.device->joints.size());
      }
    } else {
      valid += " (no Device is defined above)";
    }
    Error(position, "probe '" + probe.name + "': unknown frame '" + frame + "' " +
                        std::string(role) + DidYouMean(frame, names) + "; use " + valid);
    return false;
  }

  const TranslateOptions& options_;
  Diagnostics* diagnostics_;
  Script script_;
  std::map<std::string, Definition> defined_;
  std::map<std::string, SourcePosition> all_definitions_;
};

}  // namespace

Script ResolveScript(std::vector<Command> commands, const TranslateOptions& options,
                     Diagnostics* diagnostics) {
  Resolver resolver(options, diagnostics);
  resolver.CollectLaterDefinitions(commands);
  for (Command& command : commands) {
    std::visit([&](auto& c) { resolver.Resolve(c); }, command);
  }
  return resolver.Take();
}

}  // namespace mbstream::scene_script
