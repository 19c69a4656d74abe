// Imports a URDF robot description into a Model.
//
// Supported: a tree of revolute, continuous (revolute without limits), prismatic and fixed
// joints, with a fixed base, or a free one: a 'floating' joint from the root link (a free
// joint, 7 position and 6 velocity coordinates; its child starts at the joint's <origin>), or
// UrdfImportOptions::floating_base (docs/worlds.md); <limit> (position, velocity, effort),
// <dynamics damping>; <inertial> (origin xyz + rpy, mass, inertia) in SI units. Links on fixed
// joints are merged into the body they hang from and stay available as frames. mbstream extension:
// <mbstream:rotor_inertia value="..."/> inside a <joint> gives the rotor (reflected)
// inertia, kg*m^2 for revolute and kg for prismatic joints (declare
// xmlns:mbstream="urn:mbstream" on <robot> for namespace-aware tools).
//
// The TCP is the link named "tcp" (any case) or "tool0"; otherwise the first leaf link on
// a fixed joint of the last moving body; otherwise there is none (a warning says so).
//
// Bad input throws InputError with a message "FILE:LINE: joint 'NAME': what is wrong;
// what to do" (or link 'NAME'; LINE when known): XML or URDF that TinyXML or urdfdom
// cannot parse (urdfdom's own words quoted), a duplicate link or joint name, a link with
// two parents or a closed loop, a planar joint, a floating joint whose parent is not the root, a
// moving link without positive mass, an unphysical inertia, a zero axis, lower limit > upper,
// negative limits or damping. Input that is merely odd imports with a warning in the same form: a
// non-unit axis (normalised), a revolute joint without <limit> (unlimited), zero effort or velocity
// limits (read as none), an empty position range, a mass below 1e-6 kg, a scaled mesh, a visual
// mesh that is not supplied (collision meshes not supplied: one warning), ignored features
// (friction, <mimic> unless coupled, limits of a continuous joint), no TCP, no moving joint. A
// <mimic> is a coupling of two joints with couple_mimic (urdf_mimic.h).
#pragma once

#include <set>
#include <string>
#include <vector>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/parse/mesh_source.h"

namespace mbstream {

struct UrdfImport {
  Model model;
  std::vector<LoopClosure> loops;  // the <mimic> couplings (couple_mimic), in joint order
  std::vector<std::string> warnings;
  std::vector<std::string> mesh_files;  // every visual/collision <mesh filename>, as written
};

struct UrdfImportOptions {
  // Repair the defects published URDFs commonly carry (server/parse/urdf_repairs.h): an
  // unphysical inertia tensor, a negative velocity or effort limit, a moving link without
  // mass; each repair is a warning "FILE:LINE: link 'NAME': repaired: ...". Off: errors.
  bool repair = false;
  // Most links and named points of the model (0: only the reader's own ceiling,
  // shared/model_files/xml_shape.h): checked on the text before any parse and on the model
  // built; over it, LimitError naming --max-links.
  int max_links = 0;
  // Hold each joint with a <mimic> to its leader (a coupling in `loops`); off: the joint
  // moves freely, with a warning.
  bool couple_mimic = false;
  // The root link moves freely: a free joint to the world named after the link (x y z qw qx
  // qy qz, 6 velocities), the root's inertia its body's. A root link named "world" (whose
  // floating joint already frees the base) is refused with it.
  bool floating_base = false;
  // The collision meshes' bytes (mesh_source.h): each mesh <collision> becomes its convex
  // pieces (collision_reading.h). Empty: none is supplied (each mesh collision skipped, one
  // warning). ImportUrdfFile: the files found as `mbstream submit` finds them, when not given.
  MeshSource collision_meshes = {};
};

// Imports URDF XML `text`. `source` names the file in messages. `assets` are the mesh
// files the user supplied, each under one of the names UrdfMeshAssetNames gives; a mesh
// referenced by a visual or collision and not among them is a warning (the physics never
// reads a mesh).
UrdfImport ImportUrdf(const std::string& text, const std::string& source,
                      const std::set<std::string>& assets, const UrdfImportOptions& options = {});

// Reads and imports the file at `path`. A mesh counts as supplied when its file exists,
// looked up relative to the URDF's directory with any package:// or file:// prefix
// stripped (for package://PKG/rest also as rest, and by base name).
UrdfImport ImportUrdfFile(const std::string& path, const UrdfImportOptions& options = {});

}  // namespace mbstream
