#include "viewer/model/shape_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <Eigen/Geometry>

#include "viewer/script/polyprism_outline.h"

namespace mbstream::viewer {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// A prism over an anticlockwise outline, from z = 0 to z = height.
Mesh Extrude(const std::vector<Vector2d>& outline, double height) {
  Mesh mesh;
  const int n = static_cast<int>(outline.size());
  for (const Vector2d& p : outline) mesh.points.emplace_back(p.x(), p.y(), 0.0);
  for (const Vector2d& p : outline) mesh.points.emplace_back(p.x(), p.y(), height);
  std::vector<int> bottom, top;
  for (int i = 0; i < n; ++i) {
    bottom.push_back(n - 1 - i);
    top.push_back(n + i);
  }
  mesh.faces.push_back(bottom);
  mesh.faces.push_back(top);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    mesh.faces.push_back({i, j, n + j, n + i});
  }
  return mesh;
}

std::vector<Vector2d> RegularPolygon(double radius, int sides) {
  std::vector<Vector2d> polygon;
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * std::numbers::pi * i / sides;
    polygon.emplace_back(radius * std::cos(a), radius * std::sin(a));
  }
  return polygon;
}

}  // namespace

Mesh CylinderMesh(const scene_script::CylinderShape& cylinder) {
  return Extrude(RegularPolygon(cylinder.diameter / 2, cylinder.resolution), cylinder.length);
}

Mesh ConeMesh(const scene_script::ConeShape& cone) {
  Mesh mesh;
  const int n = cone.resolution;
  const Eigen::Quaterniond turn =
      Eigen::Quaterniond::FromTwoVectors(Vector3d::UnitZ(), cone.direction.normalized());
  for (const Vector2d& p : RegularPolygon(cone.diameter / 2, n)) {
    mesh.points.push_back(cone.center + turn * Vector3d(p.x(), p.y(), 0));
  }
  mesh.points.push_back(cone.center + turn * Vector3d(0, 0, cone.length));
  std::vector<int> base;
  for (int i = 0; i < n; ++i) base.push_back(n - 1 - i);
  mesh.faces.push_back(base);
  for (int i = 0; i < n; ++i) mesh.faces.push_back({i, (i + 1) % n, n});
  return mesh;
}

Mesh CubeMesh(const scene_script::CubeShape& cube) {
  const Vector3d& s = cube.size;
  return Extrude({{0, 0}, {s.x(), 0}, {s.x(), s.y()}, {0, s.y()}}, s.z());
}

Mesh SphereMesh(const scene_script::SphereShape& sphere) {
  Mesh mesh;
  const int around = std::max(3, sphere.resolution);
  const int rings = std::max(2, sphere.resolution / 2);
  const double r = sphere.radius;
  mesh.points.emplace_back(0, 0, -r);  // south pole: 0
  for (int ring = 1; ring < rings; ++ring) {
    const double phi = -std::numbers::pi / 2 + std::numbers::pi * ring / rings;
    for (int i = 0; i < around; ++i) {
      const double theta = 2 * std::numbers::pi * i / around;
      mesh.points.emplace_back(r * std::cos(phi) * std::cos(theta),
                               r * std::cos(phi) * std::sin(theta), r * std::sin(phi));
    }
  }
  const int north = static_cast<int>(mesh.points.size());
  mesh.points.emplace_back(0, 0, r);
  auto at = [&](int ring, int i) { return 1 + (ring - 1) * around + (i % around); };
  for (int i = 0; i < around; ++i) {
    mesh.faces.push_back({0, at(1, i + 1), at(1, i)});
    mesh.faces.push_back({north, at(rings - 1, i), at(rings - 1, i + 1)});
    for (int ring = 1; ring + 1 < rings; ++ring) {
      mesh.faces.push_back({at(ring, i), at(ring, i + 1), at(ring + 1, i + 1), at(ring + 1, i)});
    }
  }
  return mesh;
}

Mesh PolyprismMesh(const scene_script::PolyprismShape& prism) {
  scene_script::Diagnostics ignored;  // the translator already reported these
  std::vector<Vector2d> outline = scene_script::PolyprismOutline(prism, &ignored);
  if (scene_script::TwiceSignedArea(outline) < 0) std::reverse(outline.begin(), outline.end());
  return Extrude(outline, prism.height);
}

Mesh ModuleMesh(const scene_script::ModuleShape& module) {
  Mesh mesh;
  std::map<int, int> index;
  for (size_t i = 0; i < module.points.size(); ++i) {
    index[module.point_ids[i]] = static_cast<int>(i);
    mesh.points.push_back(module.points[i]);
  }
  for (const std::vector<int>& polygon : module.polygons) {
    std::vector<int> face;
    for (int id : polygon) {
      if (const auto it = index.find(id); it != index.end()) face.push_back(it->second);
    }
    if (face.size() >= 3) mesh.faces.push_back(std::move(face));
  }
  return mesh;
}

}  // namespace mbstream::viewer
