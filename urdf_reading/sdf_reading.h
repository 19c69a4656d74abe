// One reading of an SDFormat (1.6 and later) model for the server's importer and the viewer,
// through libsdformat (sdf::Root resolves frames and poses relative to frames): the shape
// check before any parse, the file's one model, its spanning tree and cut joints, the link
// frames, and the visuals (geometry, pose, material) the viewer draws. No physics: the
// server builds its Model from this (server/parse/sdf_import.h), the viewer its scene
// (viewer/model/sdf_scene.h), so both agree on joint order, cut joints and mesh files.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Geometry>
#include <sdf/Joint.hh>
#include <sdf/Model.hh>
#include <sdf/Root.hh>

namespace mbstream::urdf_reading {

inline constexpr char kSdfWorld[] = "world";

struct SdfLoadOptions {
  // Most <link> elements (--max-links); 0: no limit. Over it: LimitError, before any parse.
  int max_links = 0;
};

// A loaded SDFormat file and its one model: the file's top-level <model>, or the one model
// of its one <world>.
class SdfFile {
 public:
  // Checks the shape of `text` as a URDF's is (xml_shape.h: nesting, attributes, element
  // count, encodings, entities; InputError "SOURCE:LINE: ..."), counts its links against
  // options.max_links (LimitError), then loads it. Throws InputError "SOURCE[:LINE]: ..." for
  // SDFormat's own errors (quoted), two worlds, a world without exactly one model, no model.
  SdfFile(const std::string& text, std::string source, const SdfLoadOptions& options = {});

  const sdf::Model& model() const { return *model_; }
  const std::string& source() const { return source_; }
  // "SOURCE:LINE" of an element (SOURCE alone when the line is unknown).
  std::string Where(const sdf::ElementPtr& element) const;

 private:
  std::unique_ptr<sdf::Root> root_;
  const sdf::Model* model_ = nullptr;
  std::string source_;
};

// One joint of the file, as the tree sees it.
struct SdfJointOutline {
  const sdf::Joint* joint = nullptr;
  std::string parent, child;  // link names, "world" for the world
  std::string where;          // "SOURCE:LINE"
};

// The spanning tree, breadth-first from the world: each link in turn (in the order
// reached) takes its joints in file order; a joint whose child has no parent yet moves that
// child, a joint whose child already has one closes a loop and is cut. Deterministic.
struct SdfTree {
  std::vector<SdfJointOutline> joints;  // every joint, in file order
  std::vector<size_t> tree;             // indices into joints: the tree's, breadth-first
  std::vector<size_t> cut;              // indices into joints: the cut ones, in file order
};

// Throws InputError "SOURCE:LINE: what; what to do" for a nested model, a joint naming a link
// the model lacks, a joint type mbstream does not simulate (universal, screw, gearbox,
// revolute2), a link or joint not reached from the world.
SdfTree ChooseSdfTree(const SdfFile& file);

// A ball joint inside the tree moves its child by three revolute joints through its centre
// (the joint frame's origin): about the joint frame's x axis, then about y and z as turned by
// the ones before (Cardan angles x-y-z: R = Rx(q_x) Ry(q_y) Rz(q_z), rad), named "JOINT.x",
// "JOINT.y", "JOINT.z" (`axis` 0, 1, 2) in the results and the viewer's chain; the two links
// between them, massless, take the first two names. The angles lock at q_y = +-90 degrees
// (the child's z axis along the joint frame's x axis), where a run stops and says so
// (server/model/ball_joint.h).
std::string SdfBallAxisName(const std::string& joint, int axis);

// `pose` resolved in the model frame (X_M?). Throws InputError "WHERE: WHAT: its pose cannot
// be resolved: ...".
Eigen::Isometry3d ModelFramePose(const sdf::SemanticPose& pose, const std::string& what,
                                 const std::string& where);

// Each tree link's frame in the model frame, F_L, in SdfTree::tree order after "world"
// (identity): a moving link's frame is its joint's frame (as in URDF), a link on a fixed
// joint keeps its own pose.
struct SdfLinkFrame {
  std::string link;
  Eigen::Isometry3d X_ML = Eigen::Isometry3d::Identity();
};
std::vector<SdfLinkFrame> SdfLinkFrames(const SdfFile& file, const SdfTree& tree);

// A tree joint's unit axis in its own frame J (X_MJ its frame in the model frame). Throws
// InputError for no <axis> or a zero one.
Eigen::Vector3d SdfJointAxis(const SdfFile& file, const SdfJointOutline& joint,
                             const Eigen::Isometry3d& X_MJ);

// What a <visual> draws.
struct SdfBox {
  Eigen::Vector3d size;  // m
};
struct SdfCylinder {
  double radius = 0, length = 0;  // m, about the visual frame's z, centred
};
struct SdfSphere {
  double radius = 0;  // m
};
struct SdfMesh {
  std::string uri;  // as written
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};
struct SdfVisual {
  std::string link;  // the link it belongs to
  std::string name;
  std::string where;  // "SOURCE:LINE"
  std::variant<SdfBox, SdfCylinder, SdfSphere, SdfMesh> geometry;
  Eigen::Isometry3d X_MV = Eigen::Isometry3d::Identity();  // its frame in the model frame
  std::optional<Eigen::Vector3d> diffuse, ambient;         // <material> colours given, RGB
};

// The visuals of every link, in file order. A geometry without a drawing here (plane,
// capsule, ellipsoid, heightmap, polyline, empty) is skipped with a warning in `*warnings`.
std::vector<SdfVisual> SdfVisuals(const SdfFile& file, std::vector<std::string>* warnings);

// The <mesh><uri> of the visuals (and the collisions) of every link, in file order, each once.
struct SdfMeshes {
  std::vector<std::string> visual, collision;
};
SdfMeshes MeshesOf(const sdf::Model& model);

// MeshesOf the model of SDFormat `text`; empty when the text fails the XML shape check or
// libsdformat cannot read it (hostile text never reaches libsdformat).
SdfMeshes ReadSdfMeshes(const std::string& text);

// Throws an InputError listing libsdformat's `errors`, each as source:line: message.
[[noreturn]] void ThrowSdfErrors(const std::string& source, const sdf::Errors& errors);

}  // namespace mbstream::urdf_reading
