// Imports an SDFormat (1.6 and later) file into a Model and its loop closures.
//
// Read through shared/model_files/sdf_reading.h (libsdformat's sdf::Root, which resolves frames and
// poses relative to frames; the reading the viewer shares). The file holds a top-level
// <model>, or a <world> of one or more models, inline or <include>d (includes are resolved
// only when SdfImportOptions::includes says where: the server never reads a file a model
// names), nested models too. In a world of several models every link, joint and coordinate
// is named MODEL::NAME (docs/worlds.md). Links carry <inertial>; joints are revolute,
// continuous (revolute without limits), prismatic, fixed or ball, with <axis> (<xyz>,
// <limit>, <dynamics damping>). A ball joint inside the tree moves its child by one
// quaternion joint about its frame's origin (JointType::kBall: coordinates JOINT.qw .qx .qy .qz,
// velocities JOINT.wx .wy .wz; docs/free_bodies.md); a cut ball joint is a loop closure. A
// <static> model's links are
// fixed to the world where they stand; a model whose canonical link has no joint to the world
// is a free body: its canonical link gets a free joint named after the link.
//
// The spanning tree is chosen model by model, breadth-first from the world: starting at
// "world", each link in turn (in the order reached) takes its joints in file order; a joint
// whose child has no parent yet moves that child, and a joint whose child already has one
// closes a loop and is cut: it becomes a LoopClosure (server/model/loop_closure.h), listed in
// file order. The result is deterministic. A moving link's frame in the Model is its joint's
// frame (as in URDF, where the link frame is the joint frame); links on fixed joints, welded
// and free links keep their own.
//
// Bad input (after the shape check, see ImportSdf) throws InputError "FILE:LINE: what is wrong;
// what to do": SDFormat's own errors (quoted), no model, two worlds, an include not found (with
// the places tried), a joint type mbstream does not simulate (universal, screw, gearbox,
// revolute2), a link not reachable from the world through parent-to-child joints.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/parse/mesh_source.h"
#include "shared/model_files/sdf_reading.h"

namespace mbstream {

struct SdfImport {
  Model model;                          // the spanning tree
  std::vector<LoopClosure> loops;       // the cut joints, in file order
  std::vector<std::string> warnings;    // "FILE:LINE: ..." for input that is merely odd
  std::vector<std::string> mesh_files;  // every visual/collision <mesh><uri>, as written
};

// The <mesh><uri> of the visuals (and the collisions) of every link of SDFormat `text`, in
// file order, each once; empty when the text fails the XML shape check or libsdformat cannot
// read it (the import says why). The reading is shared/model_files's, which the viewer shares.
using model_files::ReadSdfMeshes;
using model_files::SdfMeshes;

struct SdfImportOptions {
  // Most <link> elements (--max-links); 0: no limit. Over it: LimitError, before any parse.
  int max_links = 0;
  // Where <include>s are found (a reading on the user's machine); none: refused.
  std::optional<model_files::SdfIncludePath> includes = std::nullopt;
  // The collision meshes' bytes (mesh_source.h); empty: none is supplied (each mesh collision
  // skipped, one warning). ImportSdfFile: the files beside the model, when not given.
  MeshSource collision_meshes = {};
};

// Imports SDFormat XML `text`; `source` names the file in messages. Before libsdformat
// parses it, the text's shape is checked as a URDF's is (shared/model_files/xml_shape.h: nesting,
// attributes per element, element count, encodings, entities: InputError with the line),
// and its links counted against options.max_links (LimitError).
SdfImport ImportSdf(const std::string& text, const std::string& source,
                    const SdfImportOptions& options = {});

// Reads and imports the file at `path`; its <include>s are found beside it and in the
// package path ($MBSTREAM_PACKAGE_PATH) unless options.includes says otherwise.
SdfImport ImportSdfFile(const std::string& path, const SdfImportOptions& options = {});

}  // namespace mbstream
