#include "tests/viewer/test_meshes.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace mbstream::viewer::testing {

namespace {

using Eigen::Vector3d;

struct Box {
  std::array<Vector3d, 8> points;
  std::array<std::array<int, 3>, 12> triangles;  // anticlockwise seen from outside
};

Box MakeBox(const Vector3d& low, const Vector3d& high) {
  Box box;
  for (int i = 0; i < 8; ++i) {
    box.points[i] = Vector3d((i & 1) ? high.x() : low.x(), (i & 2) ? high.y() : low.y(),
                             (i & 4) ? high.z() : low.z());
  }
  box.triangles = {{{0, 2, 1},
                    {1, 2, 3},
                    {4, 5, 6},
                    {5, 7, 6},
                    {0, 1, 4},
                    {1, 5, 4},
                    {2, 6, 3},
                    {3, 6, 7},
                    {0, 4, 2},
                    {2, 4, 6},
                    {1, 3, 5},
                    {3, 7, 5}}};
  return box;
}

std::string Triple(const Vector3d& v) {
  std::ostringstream out;
  out << v.x() << " " << v.y() << " " << v.z();
  return out.str();
}

std::string Base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t n = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

template <typename T>
void Append(std::string* bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  bytes->append(raw, sizeof(T));
}

}  // namespace

void WriteColladaBox(const std::filesystem::path& path, const Vector3d& low, const Vector3d& high,
                     double metres_per_unit, const std::string& up_axis, const Vector3d& colour) {
  const Box box = MakeBox(low, high);
  std::string positions, indices;
  for (const Vector3d& p : box.points) positions += Triple(p) + " ";
  for (const auto& t : box.triangles) {
    indices += std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + " ";
  }
  std::ofstream(path) << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="unit" meter=")"
                      << metres_per_unit << R"("/><up_axis>)" << up_axis << R"(</up_axis></asset>
  <library_effects><effect id="paint-effect"><profile_COMMON><technique sid="common"><phong>
    <diffuse><color sid="diffuse">)"
                      << Triple(colour) << R"( 1</color></diffuse>
  </phong></technique></profile_COMMON></effect></library_effects>
  <library_materials><material id="paint" name="paint">
    <instance_effect url="#paint-effect"/></material></library_materials>
  <library_geometries><geometry id="box" name="box"><mesh>
    <source id="box-positions"><float_array id="box-positions-array" count="24">)"
                      << positions << R"(</float_array>
      <technique_common><accessor source="#box-positions-array" count="8" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="box-vertices"><input semantic="POSITION" source="#box-positions"/></vertices>
    <triangles material="paint-material" count="12">
      <input semantic="VERTEX" source="#box-vertices" offset="0"/><p>)"
                      << indices << R"(</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="box-node" name="box">
    <instance_geometry url="#box"><bind_material><technique_common>
      <instance_material symbol="paint-material" target="#paint"/>
    </technique_common></bind_material></instance_geometry>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

void WriteObjBoxes(const std::filesystem::path& path, const Vector3d& low, const Vector3d& high,
                   const Vector3d& colour_a, const Vector3d& colour_b) {
  std::filesystem::path mtl = path;
  mtl.replace_extension(".mtl");
  std::ofstream(mtl) << "newmtl first\nKd " << Triple(colour_a) << "\n\nnewmtl second\nKd "
                     << Triple(colour_b) << "\n";
  std::ofstream obj(path);
  obj << "mtllib " << mtl.filename().string() << "\n";
  const Vector3d shift((high - low).x(), 0, 0);
  int base = 1;
  for (const char* material : {"first", "second"}) {
    const Box box = MakeBox(low + (base == 1 ? Vector3d::Zero() : shift),
                            high + (base == 1 ? Vector3d::Zero() : shift));
    for (const Vector3d& p : box.points) obj << "v " << Triple(p) << "\n";
    obj << "usemtl " << material << "\n";
    for (const auto& t : box.triangles) {
      obj << "f " << base + t[0] << " " << base + t[1] << " " << base + t[2] << "\n";
    }
    base += 8;
  }
}

void WriteStlBox(const std::filesystem::path& path, const Vector3d& low, const Vector3d& high,
                 bool binary) {
  const Box box = MakeBox(low, high);
  if (!binary) {
    std::ofstream out(path);
    out << "solid box\n";
    for (const auto& t : box.triangles) {
      const Vector3d n = (box.points[t[1]] - box.points[t[0]])
                             .cross(box.points[t[2]] - box.points[t[0]])
                             .normalized();
      out << " facet normal " << Triple(n) << "\n  outer loop\n";
      for (int k : t) out << "   vertex " << Triple(box.points[k]) << "\n";
      out << "  endloop\n endfacet\n";
    }
    out << "endsolid box\n";
    return;
  }
  std::string bytes(80, ' ');
  Append<uint32_t>(&bytes, 12);
  for (const auto& t : box.triangles) {
    const Vector3d n = (box.points[t[1]] - box.points[t[0]])
                           .cross(box.points[t[2]] - box.points[t[0]])
                           .normalized();
    for (int c = 0; c < 3; ++c) Append<float>(&bytes, static_cast<float>(n[c]));
    for (int k : t) {
      for (int c = 0; c < 3; ++c) Append<float>(&bytes, static_cast<float>(box.points[k][c]));
    }
    Append<uint16_t>(&bytes, 0);
  }
  std::ofstream(path, std::ios::binary) << bytes;
}

void WriteGltfBox(const std::filesystem::path& path, const Vector3d& low, const Vector3d& high,
                  const Vector3d& colour) {
  const Box box = MakeBox(low, high);
  std::string buffer;
  for (const Vector3d& p : box.points) {
    for (int c = 0; c < 3; ++c) Append<float>(&buffer, static_cast<float>(p[c]));
  }
  for (const auto& t : box.triangles) {
    for (int k : t) Append<uint16_t>(&buffer, static_cast<uint16_t>(k));
  }
  std::ostringstream json;
  json << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
       << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],)"
       << R"("materials":[{"pbrMetallicRoughness":{"baseColorFactor":[)" << colour.x() << ","
       << colour.y() << "," << colour.z() << R"(,1]}}],)"
       << R"("buffers":[{"byteLength":)" << buffer.size()
       << R"(,"uri":"data:application/octet-stream;base64,)" << Base64(buffer) << R"("}],)"
       << R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":96,"target":34962},)"
       << R"({"buffer":0,"byteOffset":96,"byteLength":72,"target":34963}],)"
       << R"("accessors":[{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","min":[)"
       << low.x() << "," << low.y() << "," << low.z() << R"(],"max":[)" << high.x() << ","
       << high.y() << "," << high.z() << R"(]},)"
       << R"({"bufferView":1,"componentType":5123,"count":36,"type":"SCALAR"}]})";
  std::ofstream(path) << json.str();
}

void WritePlyBox(const std::filesystem::path& path, const Vector3d& low, const Vector3d& high) {
  const Box box = MakeBox(low, high);
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
         "property float z\nelement face 12\nproperty list uchar int vertex_indices\n"
         "end_header\n";
  for (const Vector3d& p : box.points) out << Triple(p) << "\n";
  for (const auto& t : box.triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
}

}  // namespace mbstream::viewer::testing
