// The commands of a scene script as the parser reads them (lengths mm, angles degrees).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "viewer/script/source_position.h"
#include "viewer/script/transform_clause.h"

namespace mbstream::scene_script {

// ---- Device -------------------------------------------------------------------------

enum class JointType { kRevolute, kPrismatic };

struct JointDeclaration {
  SourcePosition position;  // of the word `Joint`
  int number = 0;           // 1-based, as written
  int parent = 0;           // frame it hangs from: the previous joint, or Extend's k
  TransformClause pre;
  JointType type = JointType::kRevolute;
  int axis = 2;  // 0 = x, 1 = y, 2 = z of the joint frame
  TransformClause post;
};

struct ExtendDeclaration {
  SourcePosition position;
  int frame = 0;
};

// Device Title (Shift ... Euler ... LBox blen) Joint ... Tcp (...) Extend k Initial (...);
struct DeviceCommand {
  SourcePosition position;
  std::string name;
  SourcePosition name_position;
  TransformClause placement;  // the device base in World
  std::optional<double> lbox_mm;
  std::vector<JointDeclaration> joints;
  std::vector<ExtendDeclaration> extends;
  std::optional<TransformClause> tcp;  // relative to frame tcp_frame
  int tcp_frame = 0;
  SourcePosition tcp_position;
  std::optional<std::vector<double>> initial;  // degrees or mm, one per joint
  SourcePosition initial_position;
};

// ---- Parts ----------------------------------------------------------------------------

// Cylinder Title dia D res N len L;  axis z, from z = 0 to z = L.
struct CylinderShape {
  double diameter = 0;
  int resolution = 0;
  double length = 0;
};

// Cone Title (Center x y z Direction x y z) dia D res N len H;  base centre at Center,
// apex at Center + H * Direction / |Direction|.
struct ConeShape {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  double diameter = 0;
  int resolution = 0;
  double length = 0;
};

// Cube Title xLen yLen zLen;  from the origin to (xLen, yLen, zLen).
struct CubeShape {
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
};

// Sphere Title radius R res N;  centred at the origin.
struct SphereShape {
  double radius = 0;
  int resolution = 0;
};

// One step of a Polyprism outline: a straight edge, or an arc, to `to`.
struct PolyprismStep {
  SourcePosition position;
  Eigen::Vector2d to = Eigen::Vector2d::Zero();
  bool arc = false;
  bool large = false;  // the long arc instead of the short one
  double radius = 0;   // > 0 clockwise, < 0 anticlockwise
  int resolution = 0;  // segments of the arc
};

// Polyprism Title Height h x1 y1 x2 y2 ... Arc [Large] to x y radius r res n ...;
struct PolyprismShape {
  double height = 0;
  std::vector<PolyprismStep> steps;  // the first is always a point
};

// Module Title Points i x y z ... Polygons (i j k ...) ...;
struct ModuleShape {
  std::vector<int> point_ids;
  std::vector<Eigen::Vector3d> points;     // parallel to point_ids
  std::vector<std::vector<int>> polygons;  // point ids as written
};

// Part Filename;  an STL file (name without .stl), units mm.
struct StlShape {
  std::string file_name;
  std::filesystem::path resolved_path;  // set by the translator when the file is found
};

using Shape = std::variant<CylinderShape, ConeShape, CubeShape, SphereShape, PolyprismShape,
                           ModuleShape, StlShape>;

struct PartCommand {
  SourcePosition position;
  std::string keyword;  // "Cylinder", "Part", ... (canonical spelling)
  std::string name;
  SourcePosition name_position;
  Shape shape;
};

// ---- Assembly, rendering, probes -----------------------------------------------------

struct Component {
  std::string name;
  SourcePosition position;
  TransformClause placement;  // the component in the assembly's frame
};

// Set Title add comp1 (transform) comp2 (transform) ...;
struct SetCommand {
  SourcePosition position;
  std::string name;
  SourcePosition name_position;
  std::vector<Component> components;
};

// Render Title color r g b;
struct RenderCommand {
  SourcePosition position;
  std::string target;
  SourcePosition target_position;
  Eigen::Vector3d color = Eigen::Vector3d::Constant(0.5);
};

// Probe Name Frame_in (Shift ...) Refer Frame_to;
struct ProbeCommand {
  SourcePosition position;
  std::string name;
  SourcePosition name_position;
  std::string frame_in;
  SourcePosition frame_in_position;
  TransformClause offset;  // only the shift matters for a point
  std::string refer = "World";
  SourcePosition refer_position;
};

using Command = std::variant<DeviceCommand, PartCommand, SetCommand, RenderCommand, ProbeCommand>;

}  // namespace mbstream::scene_script
