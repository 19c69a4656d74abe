#include "server/parse/convex_hull.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>

#include "shared/common/check.h"

namespace mbstream {

namespace {

// qhull's messages, gathered in memory (open_memstream), for the error.
class QhullMessages {
 public:
  QhullMessages() : file_(open_memstream(&text_, &size_)) {}
  ~QhullMessages() {
    if (file_ != nullptr) std::fclose(file_);
    std::free(text_);
  }
  QhullMessages(const QhullMessages&) = delete;
  QhullMessages& operator=(const QhullMessages&) = delete;
  FILE* file() const { return file_; }
  // The first line of what qhull said ("QH6154 Qhull precision error: ...").
  std::string FirstLine() {
    if (file_ == nullptr) return "";
    std::fflush(file_);
    const std::string all = text_ == nullptr ? "" : std::string(text_, size_);
    const size_t end = all.find('\n');
    return all.substr(0, end);
  }

 private:
  char* text_ = nullptr;
  size_t size_ = 0;
  FILE* file_ = nullptr;
};

// One qhull run; frees its memory however it ends.
class Qhull {
 public:
  Qhull() { qh_zero(&qh_, nullptr); }
  ~Qhull() {
    qh_freeqhull(&qh_, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(&qh_, &curlong, &totlong);
  }
  Qhull(const Qhull&) = delete;
  Qhull& operator=(const Qhull&) = delete;
  qhT* get() { return &qh_; }

 private:
  qhT qh_;
};

}  // namespace

ConvexPolytope ConvexHullOf(const std::vector<Vector3d>& points, const std::string& what) {
  if (points.size() < 4) {
    throw InputError(what + ": " + std::to_string(points.size()) +
                     " vertices span no volume; give a mesh with at least 4 vertices that are "
                     "not in one plane (or a primitive shape)");
  }
  std::vector<coordT> coordinates;
  coordinates.reserve(3 * points.size());
  for (const Vector3d& p : points) {
    if (!p.allFinite()) {
      throw InputError(what + ": a vertex is not finite; give finite coordinates");
    }
    for (int k = 0; k < 3; ++k) coordinates.push_back(p(k));
  }
  QhullMessages messages;
  Qhull run;
  qhT* qh = run.get();
  char options[] = "qhull Qt";  // triangulated output
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coordinates.data(), False,
                                options, nullptr, messages.file());
  if (code != 0) {
    throw InputError(what + ": its vertices span no volume (all in one plane or on a line: " +
                     messages.FirstLine() +
                     "); give a mesh with volume (or a primitive shape: a box for a plate)");
  }
  auto vertices = std::make_shared<std::vector<Vector3d>>();
  auto faces = std::make_shared<std::vector<int>>();
  std::map<int, int> index;  // qhull's point id -> ours
  ConvexPolytope hull;
  facetT* facet = nullptr;
  FORALLfacets {
    if (facet->upperdelaunay || qh_setsize(qh, facet->vertices) != 3) continue;
    int corner[3];
    int n = 0;
    vertexT* vertex = nullptr;
    vertexT** vertexp = nullptr;
    FOREACHvertex_(facet->vertices) {
      const int id = qh_pointid(qh, vertex->point);
      auto [it, added] = index.emplace(id, static_cast<int>(vertices->size()));
      if (added) vertices->push_back(points[static_cast<size_t>(id)]);
      corner[n++] = it->second;
    }
    const Vector3d& a = (*vertices)[corner[0]];
    const Vector3d& b = (*vertices)[corner[1]];
    const Vector3d& c = (*vertices)[corner[2]];
    const Vector3d outward(facet->normal[0], facet->normal[1], facet->normal[2]);
    if ((b - a).cross(c - a).dot(outward) < 0.0) std::swap(corner[1], corner[2]);
    faces->push_back(3);
    for (const int k : corner) faces->push_back(k);
    ++hull.num_faces;
  }
  std::vector<int> triangles;
  for (size_t k = 0; k < faces->size(); k += 4) {
    triangles.insert(triangles.end(), faces->begin() + static_cast<long>(k) + 1,
                     faces->begin() + static_cast<long>(k) + 4);
  }
  hull.volume = MeshVolume(*vertices, triangles);
  hull.lower = hull.upper = vertices->front();
  for (const Vector3d& v : *vertices) {
    hull.lower = hull.lower.cwiseMin(v);
    hull.upper = hull.upper.cwiseMax(v);
  }
  hull.vertices = std::move(vertices);
  hull.faces = std::move(faces);
  return hull;
}

double MeshVolume(const std::vector<Vector3d>& vertices, const std::vector<int>& triangles) {
  double six = 0.0;
  for (size_t k = 0; k + 2 < triangles.size(); k += 3) {
    const Vector3d& a = vertices[static_cast<size_t>(triangles[k])];
    const Vector3d& b = vertices[static_cast<size_t>(triangles[k + 1])];
    const Vector3d& c = vertices[static_cast<size_t>(triangles[k + 2])];
    six += a.dot(b.cross(c));
  }
  return std::abs(six) / 6.0;
}

}  // namespace mbstream
