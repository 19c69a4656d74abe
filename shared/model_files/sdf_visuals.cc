// The visuals of an SDFormat file's links, as the viewer draws them.
#include <sdf/Box.hh>
#include <sdf/Cylinder.hh>
#include <sdf/Geometry.hh>
#include <sdf/Link.hh>
#include <sdf/Material.hh>
#include <sdf/Mesh.hh>
#include <sdf/Sphere.hh>
#include <sdf/Visual.hh>

#include "shared/model_files/sdf_reading.h"

namespace mbstream::model_files {

namespace {

std::optional<Eigen::Vector3d> Colour(const sdf::Material& material, const char* element,
                                      const ignition::math::Color& colour) {
  if (material.Element() == nullptr || !material.Element()->HasElement(element)) {
    return std::nullopt;
  }
  return Eigen::Vector3d(colour.R(), colour.G(), colour.B());
}

// The drawing of `geometry`, or false when it has none here.
bool Drawing(const sdf::Geometry* geometry, SdfVisual* out) {
  const sdf::GeometryType type = geometry == nullptr ? sdf::GeometryType::EMPTY : geometry->Type();
  if (type == sdf::GeometryType::BOX && geometry->BoxShape() != nullptr) {
    const ignition::math::Vector3d& size = geometry->BoxShape()->Size();
    out->geometry = SdfBox{Eigen::Vector3d(size.X(), size.Y(), size.Z())};
  } else if (type == sdf::GeometryType::CYLINDER && geometry->CylinderShape() != nullptr) {
    out->geometry =
        SdfCylinder{geometry->CylinderShape()->Radius(), geometry->CylinderShape()->Length()};
  } else if (type == sdf::GeometryType::SPHERE && geometry->SphereShape() != nullptr) {
    out->geometry = SdfSphere{geometry->SphereShape()->Radius()};
  } else if (type == sdf::GeometryType::MESH && geometry->MeshShape() != nullptr) {
    const ignition::math::Vector3d& scale = geometry->MeshShape()->Scale();
    out->geometry =
        SdfMesh{geometry->MeshShape()->Uri(), Eigen::Vector3d(scale.X(), scale.Y(), scale.Z())};
  } else {
    return false;
  }
  return true;
}

}  // namespace

std::vector<SdfVisual> SdfVisuals(const SdfFile& file, std::vector<std::string>* warnings) {
  std::vector<SdfVisual> visuals;
  for (const SdfModelEntry& entry : file.models()) {
    for (uint64_t l = 0; l < entry.model->LinkCount(); ++l) {
      const sdf::Link& link = *entry.model->LinkByIndex(l);
      for (uint64_t v = 0; v < link.VisualCount(); ++v) {
        const sdf::Visual& visual = *link.VisualByIndex(v);
        SdfVisual out;
        out.link = entry.prefix + link.Name();
        out.name = visual.Name();
        out.where = file.Where(visual.Element());
        if (!Drawing(visual.Geom(), &out)) {
          if (warnings != nullptr) {
            warnings->push_back(out.where + ": link '" + out.link + "': visual '" + visual.Name() +
                                "': its geometry is not drawn (box, cylinder, sphere and mesh "
                                "are); use one of those");
          }
          continue;
        }
        out.X_WV =
            WorldPose(entry, visual.SemanticPose(), "visual '" + visual.Name() + "'", out.where);
        if (const sdf::Material* material = visual.Material(); material != nullptr) {
          out.diffuse = Colour(*material, "diffuse", material->Diffuse());
          out.ambient = Colour(*material, "ambient", material->Ambient());
        }
        visuals.push_back(std::move(out));
      }
    }
  }
  return visuals;
}

}  // namespace mbstream::model_files
