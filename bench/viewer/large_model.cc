#include "bench/viewer/large_model.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace mbstream::viewer::bench {

namespace {

using Eigen::Vector3f;

template <typename T>
void Append(std::string* bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  bytes->append(raw, sizeof(T));
}

// A tube along z from 0 to `length`, radius bulging with a ripple unique to `seed`, with
// `rings` x `around` quads (2 triangles each) plus its two caps.
long long WriteTube(const std::filesystem::path& path, int rings, int around, float radius,
                    float length, int seed) {
  auto point = [&](int ring, int i) {
    const float z = length * ring / rings;
    const float a = 2 * static_cast<float>(M_PI) * i / around;
    const float r = radius * (0.8f + 0.2f * std::sin(static_cast<float>(M_PI) * ring / rings)) *
                    (1 + 0.03f * std::sin(7 * a + seed));
    return Vector3f(r * std::cos(a), r * std::sin(a), z);
  };
  std::vector<std::array<Vector3f, 3>> triangles;
  for (int ring = 0; ring < rings; ++ring) {
    for (int i = 0; i < around; ++i) {
      const Vector3f a = point(ring, i), b = point(ring, i + 1), c = point(ring + 1, i + 1),
                     d = point(ring + 1, i);
      triangles.push_back({a, b, c});
      triangles.push_back({a, c, d});
    }
  }
  for (int i = 0; i < around; ++i) {
    triangles.push_back({Vector3f(0, 0, 0), point(0, i + 1), point(0, i)});
    triangles.push_back({Vector3f(0, 0, length), point(rings, i), point(rings, i + 1)});
  }
  std::string bytes(80, ' ');
  Append<uint32_t>(&bytes, static_cast<uint32_t>(triangles.size()));
  for (const auto& t : triangles) {
    const Vector3f n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    for (int c = 0; c < 3; ++c) Append<float>(&bytes, n[c]);
    for (const Vector3f& p : t) {
      for (int c = 0; c < 3; ++c) Append<float>(&bytes, p[c]);
    }
    Append<uint16_t>(&bytes, 0);
  }
  std::ofstream(path, std::ios::binary) << bytes;
  return static_cast<long long>(triangles.size());
}

}  // namespace

LargeModel WriteLargeModel(const std::filesystem::path& dir, int arms, int links_per_arm,
                           long long triangles) {
  std::filesystem::create_directories(dir / "meshes");
  LargeModel model;
  model.links = arms * links_per_arm + 1;
  const long long per_link = triangles / model.links;
  const int around = 96;
  const int rings = std::max(1, static_cast<int>((per_link - 2 * around) / (2 * around)));
  std::string urdf = "<robot name=\"large\">\n";
  const char* inertial =
      "<inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" "
      "ixz=\"0\" iyz=\"0\"/></inertial>";
  auto add_link = [&](const std::string& name, float radius, float length, int seed) {
    const std::string file = "meshes/" + name + ".stl";
    model.triangles += WriteTube(dir / file, rings, around, radius, length, seed);
    urdf += "<link name=\"" + name + "\">" + inertial + "<visual><geometry><mesh filename=\"" +
            file + "\"/></geometry><material name=\"m" + std::to_string(seed % 4) +
            "\"/></visual></link>\n";
  };
  urdf +=
      "<material name=\"m0\"><color rgba=\"0.8 0.8 0.8 1\"/></material>"
      "<material name=\"m1\"><color rgba=\"0.3 0.3 0.35 1\"/></material>"
      "<material name=\"m2\"><color rgba=\"0.9 0.5 0.1 1\"/></material>"
      "<material name=\"m3\"><color rgba=\"0.2 0.4 0.8 1\"/></material>\n";
  add_link("base", 0.25f, 0.4f, 0);
  for (int arm = 0; arm < arms; ++arm) {
    std::string parent = "base";
    const double yaw = 2 * M_PI * arm / arms;
    for (int k = 0; k < links_per_arm; ++k) {
      const std::string name = "arm" + std::to_string(arm) + "_link" + std::to_string(k);
      add_link(name, 0.05f, 0.16f, arm * links_per_arm + k + 1);
      const std::string origin = k == 0 ? "<origin xyz=\"" + std::to_string(0.2 * std::cos(yaw)) +
                                              " " + std::to_string(0.2 * std::sin(yaw)) +
                                              " 0.4\" rpy=\"0 0.9 " + std::to_string(yaw) + "\"/>"
                                        : "<origin xyz=\"0 0 0.16\" rpy=\"0 0.12 0\"/>";
      urdf += "<joint name=\"" + name + "_joint\" type=\"revolute\"><parent link=\"" + parent +
              "\"/><child link=\"" + name + "\"/>" + origin + "<axis xyz=\"0 " +
              (k % 2 ? "0 1" : "1 0") +
              "\"/><limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"2\"/></joint>\n";
      parent = name;
    }
  }
  urdf += "</robot>\n";
  model.urdf = dir / "large.urdf";
  std::ofstream(model.urdf) << urdf;
  return model;
}

}  // namespace mbstream::viewer::bench
