// Small URDFs written as strings, and helpers to import them, for the importer's tests.
//
// Robot() puts <robot> on line 1 and the base link on line 2; each LinkXml() and
// JointXml() is one line, so the line numbers in messages are predictable.
#pragma once

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "server/parse/urdf_import.h"
#include "shared/common/check.h"

namespace mbstream::testing {

// 1 kg at the link origin, 0.1 kg*m^2 about each axis.
inline const std::string kInertial =
    R"(<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>)";

// A revolute joint's default contents: axis z, limits +-1 rad, 10 N*m, 2 rad/s.
inline const std::string kAxisAndLimits =
    R"(<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/>)";

// An <inertial> with `mass` (kg) and the given moments and products (kg*m^2).
inline std::string InertialXml(const std::string& mass, const std::string& ixx,
                               const std::string& iyy, const std::string& izz,
                               const std::string& ixy = "0", const std::string& origin = "") {
  return "<inertial>" + origin + "<mass value=\"" + mass + "\"/><inertia ixx=\"" + ixx +
         "\" iyy=\"" + iyy + "\" izz=\"" + izz + "\" ixy=\"" + ixy +
         "\" ixz=\"0\" iyz=\"0\"/></inertial>";
}

inline std::string LinkXml(const std::string& name, const std::string& inner = kInertial) {
  return "<link name=\"" + name + "\">" + inner + "</link>\n";
}

inline std::string JointXml(const std::string& name, const std::string& type,
                            const std::string& parent, const std::string& child,
                            const std::string& inner = kAxisAndLimits) {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
         "\"/><child link=\"" + child + "\"/>" + inner + "</joint>\n";
}

// <robot name="r"> with a base link "base" (line 2) and `body` (from line 3).
inline std::string Robot(const std::string& body) {
  return "<robot name=\"r\">\n<link name=\"base\"/>\n" + body + "</robot>\n";
}

// base -> j1 (revolute, line 4 with the default contents) -> link1 (line 3).
inline std::string OneJoint(const std::string& joint_inner = kAxisAndLimits,
                            const std::string& link_inner = kInertial,
                            const std::string& type = "revolute") {
  return Robot(LinkXml("link1", link_inner) + JointXml("j1", type, "base", "link1", joint_inner));
}

// The message of the InputError that importing `text` as "bad.urdf" throws.
inline std::string ImportError(const std::string& text, const std::set<std::string>& assets = {}) {
  try {
    ImportUrdf(text, "bad.urdf", assets);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return "";
}

// The warnings of importing `text` as "odd.urdf".
inline std::vector<std::string> ImportWarnings(const std::string& text,
                                               const std::set<std::string>& assets = {}) {
  return ImportUrdf(text, "odd.urdf", assets).warnings;
}

}  // namespace mbstream::testing
