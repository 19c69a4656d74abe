// One reading of an SDFormat (1.6 and later) file for the server's importer and the viewer,
// through libsdformat (sdf::Root resolves frames and poses relative to frames): the shape
// check before any parse, the file's models (a top-level <model>, or every <model> of its one
// <world>, nested models included) with their names scoped as docs/worlds.md says, their
// spanning tree and cut joints, the link frames in the world, and the visuals (geometry,
// pose, material) the viewer draws. No physics: the server builds its Model from this
// (server/parse/sdf_import.h), the viewer its scene (viewer/model/sdf_scene.h), so both agree
// on names, joint order, cut joints and mesh files.
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

#include "shared/model_files/sdf_includes.h"

namespace mbstream::model_files {

inline constexpr char kSdfWorld[] = "world";
// Between a model's name and the names inside it: "box::link" (SDFormat's own scoping).
inline constexpr char kSdfScope[] = "::";

struct SdfLoadOptions {
  // Most <link> elements (--max-links); 0: no limit. Over it: LimitError, before any parse.
  int max_links = 0;
  // Where an <include>'s <uri> is found (a reading on the user's machine: `mbstream submit`,
  // `simulate`, the viewer's --model). Without it an <include> is refused: the server reads
  // no file a model names (`mbstream submit` sends the included models inside the world).
  std::optional<SdfIncludePath> includes = std::nullopt;
};

// One model of the file, in document order (a nested model after the one holding it).
struct SdfModelEntry {
  const sdf::Model* model = nullptr;
  // Put before its links' and joints' names: "" for the file's one model (a top-level
  // <model>, or a world of one model), else "MODEL::" (world models), and "OUTER::INNER::"
  // for nested ones.
  std::string prefix;
  Eigen::Isometry3d X_WM = Eigen::Isometry3d::Identity();  // its frame in the world
  bool is_static = false;                                  // <static> here or in a model holding it
  int top = 0;  // index of the world-level (or top-level) model that holds it
};

// A loaded SDFormat file and its models.
class SdfFile {
 public:
  // Checks the shape of `text` as a URDF's is (xml_shape.h: nesting, attributes, element
  // count, encodings, entities; InputError "SOURCE:LINE: ..."), counts its links against
  // options.max_links (LimitError), then loads it. Throws InputError "SOURCE[:LINE]: ..." for
  // SDFormat's own errors (quoted), an <include> not found (with every place tried) or not
  // allowed, two worlds, no model. An included model's mesh written relative to its own file
  // is renamed as the world finds it (sdf_mesh_uris.h), for every reader of the file.
  SdfFile(const std::string& text, std::string source, const SdfLoadOptions& options = {});

  const std::vector<SdfModelEntry>& models() const { return models_; }
  // The world's name for a world of several models, else the one model's.
  const std::string& title() const { return title_; }
  const std::string& source() const { return source_; }
  // The world's <gravity> (m/s^2, world frame) when the file sets it; libsdformat's default
  // (0 0 -9.8) is not taken for a world that leaves it out. Empty for a top-level <model>.
  const std::optional<Eigen::Vector3d>& gravity() const { return gravity_; }
  // The file as SDFormat text with each <include> replaced by the model it names (what
  // libsdformat read, written back; default values left out), as `mbstream submit` sends a
  // world: the server then reads one file.
  std::string ExpandedText() const;
  // "FILE:LINE" of an element (the included file's path for an element read from one; the
  // source alone when the line is unknown).
  std::string Where(const sdf::ElementPtr& element) const;

 private:
  void AddModel(const sdf::Model& model, std::string prefix, const Eigen::Isometry3d& X_WM,
                bool is_static, int top);

  std::unique_ptr<sdf::Root> root_;
  std::vector<SdfModelEntry> models_;
  std::string title_;
  std::string source_;
  std::optional<Eigen::Vector3d> gravity_;
};

// How a joint of the tree came to be.
enum class SdfJointRole {
  kFile,  // a <joint> of the file
  kFree,  // a model's canonical link with no joint to the world: six degrees of freedom
  kWeld,  // a link of a <static> model, fixed to the world where it stands
};

// One joint of the file, as the tree sees it, with scoped names.
struct SdfJointOutline {
  const sdf::Joint* joint = nullptr;  // kFile only
  SdfJointRole role = SdfJointRole::kFile;
  std::string name;           // scoped; a free joint is named after its link, a weld too
  std::string parent, child;  // scoped link names, "world" for the world
  std::string where;          // "FILE:LINE"
  int model = 0;              // index into SdfFile::models()
};

// The spanning tree: model by model (world-level models in file order), breadth-first from
// the world: the model's joints to the world (in file order), or its free joint, or the welds
// of a static model, then each link in turn (in the order reached) takes its joints in file
// order; a joint whose child has no parent yet moves that child, a joint whose child already
// has one closes a loop and is cut. Deterministic. A static model's own joints move nothing
// (a warning each).
struct SdfTree {
  std::vector<SdfJointOutline> joints;  // every joint, file joints in file order first
  std::vector<size_t> tree;             // indices into joints: the tree's
  std::vector<size_t> cut;              // indices into joints: the cut ones, in file order
  std::vector<std::string> warnings;    // "FILE:LINE: ..."
};

// Throws InputError "FILE:LINE: what; what to do" for a joint naming a link its model lacks,
// a joint type mbstream does not simulate (universal, screw, gearbox, revolute2), a link or
// joint not reached from the world, two links of one scoped name.
SdfTree ChooseSdfTree(const SdfFile& file);

// A ball joint inside the tree moves its child about the joint frame's origin; its values are
// the unit quaternion of the child's rotation in the joint frame, "JOINT.qw" ".qx" ".qy" ".qz"
// (`value` 0..3, scalar first), in the results and the viewer's chain (server/model/model.h).
std::string SdfBallValueName(const std::string& joint, int value);

// `pose` resolved in the model frame of `entry`, then in the world (X_W?). Throws InputError
// "WHERE: WHAT: its pose cannot be resolved: ...".
Eigen::Isometry3d WorldPose(const SdfModelEntry& entry, const sdf::SemanticPose& pose,
                            const std::string& what, const std::string& where);

// A link of the file by scoped name, and its model, or nullptr.
struct SdfLinkRef {
  const sdf::Link* link = nullptr;
  int model = 0;
};
SdfLinkRef FindSdfLink(const SdfFile& file, const std::string& scoped_name);

// The link's own frame in the world.
Eigen::Isometry3d SdfLinkPose(const SdfFile& file, const std::string& scoped_name);

// Each tree link's frame in the world, F_L, in SdfTree::tree order after "world"
// (identity): a link moved by a revolute, prismatic or ball joint has its joint's frame (as
// in URDF); a link on a fixed joint, a weld or a free joint keeps its own pose.
struct SdfLinkFrame {
  std::string link;
  Eigen::Isometry3d X_WL = Eigen::Isometry3d::Identity();
};
std::vector<SdfLinkFrame> SdfLinkFrames(const SdfFile& file, const SdfTree& tree);

// A tree joint's unit axis in its own frame J (X_WJ its frame in the world). Throws
// InputError for no <axis> or a zero one.
Eigen::Vector3d SdfJointAxis(const SdfFile& file, const SdfJointOutline& joint,
                             const Eigen::Isometry3d& X_WJ);

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
  std::string link;  // the link it belongs to (scoped)
  std::string name;
  std::string where;  // "FILE:LINE"
  std::variant<SdfBox, SdfCylinder, SdfSphere, SdfMesh> geometry;
  Eigen::Isometry3d X_WV = Eigen::Isometry3d::Identity();  // its frame in the world
  std::optional<Eigen::Vector3d> diffuse, ambient;         // <material> colours given, RGB
};

// The visuals of every link of every model, in file order. A geometry without a drawing here
// (plane, capsule, ellipsoid, heightmap, polyline, empty) is skipped with a warning in
// `*warnings`.
std::vector<SdfVisual> SdfVisuals(const SdfFile& file, std::vector<std::string>* warnings);

// The <mesh><uri> of the visuals (and the collisions) of every link, in file order, each once.
struct SdfMeshes {
  std::vector<std::string> visual, collision;
};
SdfMeshes MeshesOf(const SdfFile& file);

// MeshesOf the models of SDFormat `text`; empty when the text fails the XML shape check or
// libsdformat cannot read it (hostile text never reaches libsdformat).
SdfMeshes ReadSdfMeshes(const std::string& text);

// Throws an InputError listing libsdformat's `errors`, each as source:line: message.
[[noreturn]] void ThrowSdfErrors(const std::string& source, const sdf::Errors& errors);

}  // namespace mbstream::model_files
