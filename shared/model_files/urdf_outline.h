// What urdfdom does not keep of a URDF document: the order of its links and joints, which
// materials carry a colour, and the text to hand to urdfdom.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace mbstream::model_files {

struct UrdfOutline {
  std::vector<std::string> link_order;   // <link> names in document order
  std::vector<std::string> joint_order;  // <joint> names in document order
  // The <mesh filename> of every visual and of every collision, as written, document order.
  std::vector<std::string> visual_meshes;
  std::vector<std::string> collision_meshes;
  // Names of the materials that have a <color> (top level or inline in a <visual>):
  // urdfdom leaves a material without one black, which is not the author's colour.
  std::set<std::string> coloured_materials;
  // The document for urdfdom: a revolute joint without <limit> (which urdfdom rejects) is
  // written as continuous, the reading the server's importer gives it (with a warning).
  std::string urdfdom_text;
  std::vector<std::string> limitless_revolute_joints;  // the joints so rewritten
};

// Reads the outline of URDF XML `text`. Returns nullopt with `*error` set when its shape is
// beyond xml_shape.h's default limits, the XML is not well formed or has no <robot> element.
std::optional<UrdfOutline> ReadUrdfOutline(const std::string& text, std::string* error);

}  // namespace mbstream::model_files
