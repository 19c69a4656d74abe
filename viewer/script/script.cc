#include "viewer/script/script.h"

namespace mbstream::scene_script {

const PartCommand* Script::FindPart(std::string_view name) const {
  for (const PartCommand& part : parts) {
    if (part.name == name) return &part;
  }
  return nullptr;
}

const SetCommand* Script::FindSet(std::string_view name) const {
  for (const SetCommand& set : sets) {
    if (set.name == name) return &set;
  }
  return nullptr;
}

const RenderCommand* Script::FindRender(std::string_view name) const {
  const RenderCommand* found = nullptr;
  for (const RenderCommand& render : renders) {
    if (render.target == name) found = &render;
  }
  return found;
}

}  // namespace mbstream::scene_script
