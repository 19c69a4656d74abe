#include "viewer/web/scene_export.h"

#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkTexture.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace mbstream::viewer {

namespace {

// The image of a textured actor as PNG bytes (empty when it has none).
std::string TexturePng(vtkActor* actor) {
  vtkTexture* texture = actor->GetTexture();
  if (!texture) return {};
  texture->Update();
  auto* image = vtkImageData::SafeDownCast(texture->GetInputDataObject(0, 0));
  if (!image) image = texture->GetInput();
  if (!image) return {};
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(image);
  writer->WriteToMemoryOn();
  writer->Write();
  vtkUnsignedCharArray* bytes = writer->GetResult();
  if (!bytes) return {};
  return std::string(reinterpret_cast<const char*>(bytes->GetPointer(0)),
                     static_cast<std::size_t>(bytes->GetNumberOfValues()));
}

// The triangles of a part actor's mapper input (polygons and strips triangulated); with a
// texture, its image (PNG, base64) and the texture coordinates per point.
nlohmann::json PartJson(vtkActor* actor, int frame) {
  nlohmann::json part;
  part["frame"] = frame;
  double colour[3];
  actor->GetProperty()->GetColor(colour);
  part["color"] = {colour[0], colour[1], colour[2]};
  part["opacity"] = actor->GetProperty()->GetOpacity();
  std::vector<float> positions;
  std::vector<float> uvs;
  std::vector<std::uint32_t> indices;
  const std::string png = TexturePng(actor);
  vtkMapper* mapper = actor->GetMapper();
  if (mapper) {
    mapper->Update();
    auto* input = vtkPolyData::SafeDownCast(mapper->GetInputDataObject(0, 0));
    if (input && input->GetNumberOfPoints() > 0) {
      vtkNew<vtkTriangleFilter> triangles;
      triangles->SetInputData(input);
      triangles->PassVertsOff();
      triangles->PassLinesOff();
      triangles->Update();
      vtkPolyData* mesh = triangles->GetOutput();
      positions.reserve(3 * static_cast<std::size_t>(mesh->GetNumberOfPoints()));
      for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i) {
        double p[3];
        mesh->GetPoint(i, p);
        for (double c : p) positions.push_back(static_cast<float>(c));
      }
      vtkDataArray* tcoords = mesh->GetPointData()->GetTCoords();
      if (!png.empty() && tcoords && tcoords->GetNumberOfComponents() >= 2) {
        uvs.reserve(2 * static_cast<std::size_t>(mesh->GetNumberOfPoints()));
        for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i) {
          uvs.push_back(static_cast<float>(tcoords->GetComponent(i, 0)));
          uvs.push_back(static_cast<float>(tcoords->GetComponent(i, 1)));
        }
      }
      vtkCellArray* polys = mesh->GetPolys();
      vtkIdType count = 0;
      const vtkIdType* ids = nullptr;
      for (polys->InitTraversal(); polys->GetNextCell(count, ids);) {
        if (count != 3) continue;
        for (int k = 0; k < 3; ++k) indices.push_back(static_cast<std::uint32_t>(ids[k]));
      }
    }
  }
  part["positions"] = Base64(positions.data(), positions.size() * sizeof(float));
  part["indices"] = Base64(indices.data(), indices.size() * sizeof(std::uint32_t));
  part["triangles"] = indices.size() / 3;
  if (!uvs.empty()) {  // VTK's texture coordinates: (0, 0) at the image's bottom left
    part["uvs"] = Base64(uvs.data(), uvs.size() * sizeof(float));
    part["texture_png"] = Base64(png.data(), png.size());
  }
  return part;
}

nlohmann::json Vector(const double v[3]) { return {v[0], v[1], v[2]}; }

}  // namespace

std::string Base64(const void* data, std::size_t size) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const unsigned v = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < size) {
    const unsigned v = (bytes[i] << 16) | (i + 1 < size ? bytes[i + 1] << 8 : 0);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string ExportSceneJson(Scene& scene, std::uint64_t version) {
  nlohmann::json out;
  out["type"] = "scene";
  out["version"] = version;
  out["title"] = scene.description().title;
  out["missing_meshes"] = scene.missing_meshes_line();  // one HUD line, "" when none
  std::vector<Eigen::Isometry3d> frames;
  scene.Frames(&frames);
  out["frames"] = frames.size();
  nlohmann::json parts = nlohmann::json::array();
  for (std::size_t i = 0; i < scene.part_actors().size(); ++i) {
    parts.push_back(PartJson(scene.part_actors()[i], scene.part_frames()[i]));
  }
  out["parts"] = std::move(parts);
  nlohmann::json probes = nlohmann::json::array();
  for (const ProbePoint& probe : scene.description().probes) {
    probes.push_back({{"name", probe.name},
                      {"frame", probe.frame},
                      {"point", {probe.point.x(), probe.point.y(), probe.point.z()}},
                      {"refer", probe.refer},
                      {"refer_name", probe.refer_name}});
  }
  out["probes"] = std::move(probes);
  out["probe_radius"] =
      scene.description().scene_box_m ? 0.012 * *scene.description().scene_box_m : 0.015;
  vtkCamera* camera = scene.renderer()->GetActiveCamera();
  out["camera"] = {{"position", Vector(camera->GetPosition())},
                   {"focal", Vector(camera->GetFocalPoint())},
                   {"up", Vector(camera->GetViewUp())},
                   {"view_angle", camera->GetViewAngle()}};
  out["ghost_opacity"] = scene.ghost() ? scene.ghost()->opacity() : 0.0;
  return out.dump();
}

}  // namespace mbstream::viewer
