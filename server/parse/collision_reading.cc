#include "server/parse/collision_reading.h"

#include <tinyxml.h>

#include <cmath>
#include <cstdlib>
#include <optional>

#include <sdf/Box.hh>
#include <sdf/Capsule.hh>
#include <sdf/Collision.hh>
#include <sdf/Cylinder.hh>
#include <sdf/Geometry.hh>
#include <sdf/Link.hh>
#include <sdf/Mesh.hh>
#include <sdf/Plane.hh>
#include <sdf/Sphere.hh>
#include <sdf/Surface.hh>

#include "server/parse/collision_meshes.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

namespace mf = model_files;

constexpr const char* kProximity = "drake:proximity_properties";

Pose PoseOf(const Eigen::Isometry3d& X) { return Pose{X.linear(), X.translation()}; }

// A rotation whose z axis is the unit vector n.
Matrix3d ZAlongNormal(const Vector3d& n) {
  const Vector3d z = Vector3d::UnitZ();
  const double c = z.dot(n);
  const Vector3d axis = z.cross(n);
  if (axis.norm() < 1e-12) {
    return c > 0 ? Matrix3d::Identity() : AxisAngleRotation(Vector3d::UnitX(), M_PI);
  }
  return AxisAngleRotation(axis.normalized(), std::atan2(axis.norm(), c));
}

// "where: link 'L': collision 'C'".
std::string WhatOf(const CollisionGeometry& g) {
  return g.where + ": link '" + g.link + "': collision '" + g.name + "'";
}

void CheckSize(const CollisionGeometry& g, const char* what, double value) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw InputError(WhatOf(g) + ": the " + std::string(what) + " is " + std::to_string(value) +
                     "; give a finite size > 0 (m)");
  }
}

void CheckShape(const CollisionGeometry& g) {
  const CollisionShape& s = g.shape;
  switch (s.type) {
    case ShapeType::kSphere:
      CheckSize(g, "sphere's radius", s.radius);
      break;
    case ShapeType::kBox:
      for (int k = 0; k < 3; ++k) CheckSize(g, "box's size", s.size(k));
      break;
    case ShapeType::kCylinder:
    case ShapeType::kCapsule:
      CheckSize(g, "radius", s.radius);
      CheckSize(g, "length", s.length);
      break;
    case ShapeType::kConvex:
    case ShapeType::kPlane:
      break;
  }
}

// A surface parameter: finite and >= 0 (a friction coefficient, a stiffness, a dissipation).
void SetSurface(const CollisionGeometry& g, const std::string& tag, const std::string& text,
                double* out) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || !std::isfinite(value) || value < 0.0) {
    throw InputError(WhatOf(g) + ": <" + tag + "> is '" + text +
                     "'; give a finite number >= 0 (docs/contact.md)");
  }
  *out = value;
}

// Which field a drake:proximity_properties child sets, or null.
double* DrakeField(const std::string& tag, SurfaceProperties* s) {
  if (tag == "drake:point_contact_stiffness") return &s->stiffness;
  if (tag == "drake:hunt_crossley_dissipation") return &s->dissipation;
  if (tag == "drake:mu_static") return &s->mu_static;
  if (tag == "drake:mu_dynamic") return &s->mu_dynamic;
  return nullptr;
}

// Static friction as the dynamic one when only the dynamic one is given (and the reverse).
void CompleteFriction(SurfaceProperties* s) {
  if (std::isnan(s->mu_static) && !std::isnan(s->mu_dynamic)) s->mu_static = s->mu_dynamic;
  if (std::isnan(s->mu_dynamic) && !std::isnan(s->mu_static)) s->mu_dynamic = s->mu_static;
  if (!std::isnan(s->mu_static) && s->mu_dynamic > s->mu_static) s->mu_static = s->mu_dynamic;
}

// The body and frame a link's geometry is fixed in, from the Model's frame of the link.
void PlaceOnLink(const Model& model, const std::string& link, const Pose& X_LG,
                 CollisionGeometry* g) {
  const int frame = model.FindFrame(link);
  MBSTREAM_CHECK_MSG(frame >= 0, "link '" + link + "' is not a frame of the model");
  g->body = model.frames[frame].body;
  g->X_BG = model.frames[frame].X_BF * X_LG;
}

// One warning for the collisions skipped (a model with many collision meshes gets one line),
// ending "; `tail`".
void WarnSkipped(const std::vector<std::string>& skipped, const std::string& tail,
                 std::vector<std::string>* warnings) {
  if (skipped.empty() || warnings == nullptr) return;
  std::string text = skipped.front();
  if (skipped.size() > 1) {
    text += "; and " + std::to_string(skipped.size() - 1) + " more: ";
    for (size_t k = 1; k < skipped.size() && k < 4; ++k) text += (k > 1 ? "; " : "") + skipped[k];
    if (skipped.size() > 4) text += "; ...";
  }
  warnings->push_back(text + "; " + tail);
}

// A <collision>'s <mesh>: its file as written and its scale.
struct MeshReference {
  std::string file;
  Vector3d scale = Vector3d::Ones();
};

// What the collisions' meshes left to say, one warning each kind.
struct MeshNotes {
  std::vector<std::string> skipped;     // geometry not simulated (another shape)
  std::vector<std::string> unsupplied;  // a mesh whose file is not supplied
  // meshes not convex: the first in full ("WHERE: mesh 'F' is not convex (...)"), the others
  // as "'F' (NN %)"
  std::vector<std::string> concave;
};

// "61 %" for a volume ratio of 0.61.
std::string Percent(double ratio) {
  return std::to_string(static_cast<int>(std::lround(100.0 * ratio))) + " %";
}

// The convex pieces of `mesh` (collision_meshes.h) as geometries like `g` (placed, its
// surface read) into model->collisions; a mesh not supplied is noted and adds nothing; a mesh
// with a piece that is not convex is noted (its hull is used).
void AddMeshPieces(const MeshReference& mesh, const CollisionGeometry& g, const MeshSource& meshes,
                   Model* model, MeshNotes* notes) {
  const std::string what = WhatOf(g) + ": mesh '" + mesh.file + "'";
  const std::optional<std::string> bytes =
      mesh.file.empty() || !meshes ? std::nullopt : meshes(mesh.file);
  if (!bytes) {
    notes->unsupplied.push_back(what + " is not supplied");
    return;
  }
  CollisionMesh read = ReadCollisionMesh(*bytes, mesh.file, mesh.scale, what);
  int concave = 0;
  double farthest = 1.0;  // the volume ratio farthest from 1
  for (size_t k = 0; k < read.pieces.size(); ++k) {
    const double ratio = read.volume_ratio[k];
    if (!(ratio >= kConvexVolumeRatio && ratio <= 2.0 - kConvexVolumeRatio)) {
      ++concave;
      if (std::abs(std::log(ratio)) > std::abs(std::log(farthest))) farthest = ratio;
    }
    CollisionGeometry piece = g;
    piece.piece = static_cast<int>(k);
    piece.shape = CollisionShape{};
    piece.shape.type = ShapeType::kConvex;
    piece.shape.convex = std::move(read.pieces[k]);
    model->collisions.push_back(std::move(piece));
  }
  if (concave == 0) return;
  const std::string pieces = read.pieces.size() == 1
                                 ? ""
                                 : ", " + std::to_string(concave) + " of its " +
                                       std::to_string(read.pieces.size()) + " pieces";
  if (notes->concave.empty()) {
    const std::string why = farthest < 1.0
                                ? "is not convex (it encloses " + Percent(farthest) +
                                      " of its hull's volume" + pieces + ")"
                                : "is not closed (its triangles enclose " + Percent(farthest) +
                                      " of its hull's volume" + pieces + ")";
    notes->concave.push_back(what + " " + why);
  } else {
    notes->concave.push_back("'" + mesh.file + "' (" + Percent(farthest) + pieces + ")");
  }
}

void WarnMeshNotes(const MeshNotes& notes, const char* shapes, std::vector<std::string>* warnings) {
  WarnSkipped(notes.skipped, std::string("skipped: they touch nothing (use ") + shapes + ")",
              warnings);
  WarnSkipped(notes.unsupplied,
              "skipped: they touch nothing (send the collision meshes: mbstream submit "
              "--with-collision)",
              warnings);
  if (notes.concave.empty() || warnings == nullptr) return;
  // One warning for the model, every file named (a humanoid has 29 such meshes).
  std::string text = notes.concave.front();
  if (notes.concave.size() > 1) {
    text += "; and " + std::to_string(notes.concave.size() - 1) + " more meshes not convex:";
    for (size_t k = 1; k < notes.concave.size(); ++k)
      text += (k > 1 ? ", " : " ") + notes.concave[k];
  }
  warnings->push_back(
      text +
      (notes.concave.size() > 1 ? "; their convex hulls are used" : "; its convex hull is used") +
      " (split a mesh into convex pieces, one object each, for a closer shape)");
}

// ---- SDFormat ----

std::string SdfText(const sdf::ElementPtr& e) {
  if (e == nullptr || e->GetValue() == nullptr) return "";
  std::string text = e->GetValue()->GetAsString();
  const size_t a = text.find_first_not_of(" \t\r\n");
  const size_t b = text.find_last_not_of(" \t\r\n");
  return a == std::string::npos ? "" : text.substr(a, b - a + 1);
}

sdf::ElementPtr SdfChild(const sdf::ElementPtr& e, const char* name) {
  if (e == nullptr || !e->HasElement(name)) return nullptr;
  return e->GetElement(name);
}

void ReadSdfSurface(const sdf::Collision& collision, CollisionGeometry* g) {
  const sdf::ElementPtr element = collision.Element();
  if (const sdf::ElementPtr proximity = SdfChild(element, kProximity)) {
    for (sdf::ElementPtr c = proximity->GetFirstElement(); c != nullptr; c = c->GetNextElement()) {
      if (double* field = DrakeField(c->GetName(), &g->surface)) {
        SetSurface(*g, c->GetName(), SdfText(c), field);
      }
    }
  }
  const sdf::ElementPtr surface = SdfChild(element, "surface");
  const sdf::ElementPtr mu = SdfChild(SdfChild(SdfChild(surface, "friction"), "ode"), "mu");
  if (mu != nullptr && std::isnan(g->surface.mu_dynamic)) {
    SetSurface(*g, "surface><friction><ode><mu", SdfText(mu), &g->surface.mu_dynamic);
  }
  CompleteFriction(&g->surface);
  if (SdfChild(SdfChild(surface, "contact"), "collide_bitmask") != nullptr &&
      collision.Surface() != nullptr && collision.Surface()->Contact() != nullptr) {
    g->collide_bitmask = collision.Surface()->Contact()->CollideBitmask();
  }
}

// The shape of `geometry` (a mesh: its reference in *mesh, the shape to come), or false
// (noted in *skipped) when it is not simulated.
bool SdfShape(const sdf::Geometry* geometry, CollisionGeometry* g, Pose* X_GS,
              std::optional<MeshReference>* mesh, std::vector<std::string>* skipped) {
  const sdf::GeometryType type = geometry == nullptr ? sdf::GeometryType::EMPTY : geometry->Type();
  CollisionShape& s = g->shape;
  if (type == sdf::GeometryType::SPHERE && geometry->SphereShape() != nullptr) {
    s.type = ShapeType::kSphere;
    s.radius = geometry->SphereShape()->Radius();
  } else if (type == sdf::GeometryType::BOX && geometry->BoxShape() != nullptr) {
    const ignition::math::Vector3d& size = geometry->BoxShape()->Size();
    s.type = ShapeType::kBox;
    s.size = Vector3d(size.X(), size.Y(), size.Z());
  } else if (type == sdf::GeometryType::CYLINDER && geometry->CylinderShape() != nullptr) {
    s.type = ShapeType::kCylinder;
    s.radius = geometry->CylinderShape()->Radius();
    s.length = geometry->CylinderShape()->Length();
  } else if (type == sdf::GeometryType::CAPSULE && geometry->CapsuleShape() != nullptr) {
    s.type = ShapeType::kCapsule;
    s.radius = geometry->CapsuleShape()->Radius();
    s.length = geometry->CapsuleShape()->Length();
  } else if (type == sdf::GeometryType::PLANE && geometry->PlaneShape() != nullptr) {
    const ignition::math::Vector3d n = geometry->PlaneShape()->Normal();
    const Vector3d normal(n.X(), n.Y(), n.Z());
    if (!(normal.norm() > 0.0) || !normal.allFinite()) {
      throw InputError(WhatOf(*g) + ": the plane's normal is zero; give a non-zero <normal>");
    }
    s.type = ShapeType::kPlane;
    X_GS->R = ZAlongNormal(normal.normalized());
  } else if (type == sdf::GeometryType::MESH && geometry->MeshShape() != nullptr) {
    const ignition::math::Vector3d scale = geometry->MeshShape()->Scale();
    *mesh = MeshReference{geometry->MeshShape()->Uri(), Vector3d(scale.X(), scale.Y(), scale.Z())};
    s.type = ShapeType::kConvex;
    return true;
  } else {
    if (skipped != nullptr) skipped->push_back(WhatOf(*g) + ": its geometry is not simulated");
    return false;
  }
  CheckShape(*g);
  return true;
}

// ---- URDF ----

std::optional<double> Number(const TiXmlElement& e, const char* attribute) {
  double value = 0.0;
  if (e.QueryDoubleAttribute(attribute, &value) != TIXML_SUCCESS) return std::nullopt;
  return value;
}

bool Triple(const TiXmlElement& e, const char* attribute, Vector3d* out) {
  const char* text = e.Attribute(attribute);
  if (text == nullptr) return false;
  char* end = nullptr;
  const char* p = text;
  for (int k = 0; k < 3; ++k) {
    (*out)(k) = std::strtod(p, &end);
    if (end == p) return false;
    p = end;
  }
  return true;
}

Pose UrdfOrigin(const TiXmlElement* origin) {
  Pose X;
  if (origin == nullptr) return X;
  Vector3d xyz = Vector3d::Zero(), rpy = Vector3d::Zero();
  Triple(*origin, "xyz", &xyz);
  Triple(*origin, "rpy", &rpy);
  X.p = xyz;
  X.R = AxisAngleRotation(Vector3d::UnitZ(), rpy.z()) *
        AxisAngleRotation(Vector3d::UnitY(), rpy.y()) *
        AxisAngleRotation(Vector3d::UnitX(), rpy.x());
  return X;
}

bool UrdfShape(const TiXmlElement* geometry, CollisionGeometry* g,
               std::optional<MeshReference>* mesh, std::vector<std::string>* skipped) {
  const TiXmlElement* shape = geometry == nullptr ? nullptr : geometry->FirstChildElement();
  const std::string tag = shape == nullptr ? "" : shape->Value();
  CollisionShape& s = g->shape;
  if (tag == "sphere") {
    s.type = ShapeType::kSphere;
    s.radius = Number(*shape, "radius").value_or(0.0);
  } else if (tag == "box") {
    s.type = ShapeType::kBox;
    if (!Triple(*shape, "size", &s.size)) s.size.setZero();
  } else if (tag == "cylinder") {
    s.type = ShapeType::kCylinder;
    s.radius = Number(*shape, "radius").value_or(0.0);
    s.length = Number(*shape, "length").value_or(0.0);
  } else if (tag == "mesh") {
    const char* file = shape->Attribute("filename");
    MeshReference reference{file == nullptr ? "" : file, Vector3d::Ones()};
    if (shape->Attribute("scale") != nullptr && !Triple(*shape, "scale", &reference.scale)) {
      throw InputError(WhatOf(*g) + ": the mesh's scale is '" + shape->Attribute("scale") +
                       "'; give three numbers");
    }
    *mesh = std::move(reference);
    s.type = ShapeType::kConvex;
    return true;
  } else {
    if (skipped != nullptr) skipped->push_back(WhatOf(*g) + ": its geometry is not simulated");
    return false;
  }
  CheckShape(*g);
  return true;
}

void ReadUrdfSurface(const TiXmlElement& collision, CollisionGeometry* g) {
  const TiXmlElement* proximity = collision.FirstChildElement(kProximity);
  if (proximity == nullptr) return;
  for (const TiXmlElement* c = proximity->FirstChildElement(); c != nullptr;
       c = c->NextSiblingElement()) {
    if (double* field = DrakeField(c->Value(), &g->surface)) {
      const char* value = c->Attribute("value");
      SetSurface(*g, c->Value(), value == nullptr ? "" : value, field);
    }
  }
  CompleteFriction(&g->surface);
}

}  // namespace

void ReadSdfCollisions(const mf::SdfFile& file, const std::map<std::string, Pose>& link_frames,
                       const MeshSource& meshes, Model* model, std::vector<std::string>* warnings) {
  MeshNotes notes;
  for (const mf::SdfModelEntry& entry : file.models()) {
    for (uint64_t l = 0; l < entry.model->LinkCount(); ++l) {
      const sdf::Link& link = *entry.model->LinkByIndex(l);
      const std::string scoped = entry.prefix + link.Name();
      const auto frame = link_frames.find(scoped);
      if (frame == link_frames.end()) continue;  // not in the tree (the import refused it)
      for (uint64_t c = 0; c < link.CollisionCount(); ++c) {
        const sdf::Collision& collision = *link.CollisionByIndex(c);
        CollisionGeometry g;
        g.name = collision.Name();
        g.link = scoped;
        g.where = file.Where(collision.Element());
        Pose X_GS;  // a plane's normal as the shape frame's z
        std::optional<MeshReference> mesh;
        if (!SdfShape(collision.Geom(), &g, &X_GS, &mesh, &notes.skipped)) continue;
        ReadSdfSurface(collision, &g);
        const Pose X_WG = PoseOf(
            mf::WorldPose(entry, collision.SemanticPose(), "collision '" + g.name + "'", g.where));
        PlaceOnLink(*model, scoped, frame->second.Inverse() * X_WG * X_GS, &g);
        if (mesh) {
          AddMeshPieces(*mesh, g, meshes, model, &notes);
        } else {
          model->collisions.push_back(std::move(g));
        }
      }
    }
  }
  WarnMeshNotes(notes, "a sphere, box, cylinder, capsule, plane or mesh", warnings);
}

void ReadUrdfCollisions(const std::string& text, const std::string& source,
                        const MeshSource& meshes, Model* model,
                        std::vector<std::string>* warnings) {
  TiXmlDocument document;
  document.Parse(text.c_str(), nullptr, TIXML_ENCODING_UTF8);
  const TiXmlElement* robot = document.FirstChildElement("robot");
  if (document.Error() || robot == nullptr) return;  // the scan before said why
  MeshNotes notes;
  for (const TiXmlElement* link = robot->FirstChildElement("link"); link != nullptr;
       link = link->NextSiblingElement("link")) {
    const char* link_name = link->Attribute("name");
    if (link_name == nullptr || model->FindFrame(link_name) < 0) continue;
    for (const TiXmlElement* e = link->FirstChildElement("collision"); e != nullptr;
         e = e->NextSiblingElement("collision")) {
      CollisionGeometry g;
      const char* name = e->Attribute("name");
      g.name = name == nullptr ? "" : name;
      g.link = link_name;
      g.where = source + ":" + std::to_string(e->Row());
      std::optional<MeshReference> mesh;
      if (!UrdfShape(e->FirstChildElement("geometry"), &g, &mesh, &notes.skipped)) continue;
      ReadUrdfSurface(*e, &g);
      PlaceOnLink(*model, g.link, UrdfOrigin(e->FirstChildElement("origin")), &g);
      if (mesh) {
        AddMeshPieces(*mesh, g, meshes, model, &notes);
      } else {
        model->collisions.push_back(std::move(g));
      }
    }
  }
  WarnMeshNotes(notes, "a sphere, box, cylinder or mesh", warnings);
}

}  // namespace mbstream
