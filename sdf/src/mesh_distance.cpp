#include "marchcheck/sdf/mesh_distance.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>

namespace marchcheck::sdf {

namespace {

using glm::dvec3;
constexpr std::uint32_t kLeafSize = 4;

std::string edge_name(std::uint32_t a, std::uint32_t b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

// Angle at corner a of triangle abc.
double corner_angle(dvec3 a, dvec3 b, dvec3 c) {
  const dvec3 u = glm::normalize(b - a), v = glm::normalize(c - a);
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

}  // namespace

MeshDistance::MeshDistance(const TriangleMesh& mesh) : mesh_(mesh) {
  const auto& vs = mesh.vertices;
  const auto& ts = mesh.triangles;
  if (ts.empty()) throw MeshShapeError("the mesh has no triangles");
  std::vector<dvec3> face_normal(ts.size());
  std::vector<dvec3> vertex_normal(vs.size(), dvec3(0));
  // Each directed edge and the face it belongs to: a closed, consistently oriented mesh has every edge once in
  // each direction.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> directed;
  double volume6 = 0;
  for (std::uint32_t f = 0; f < ts.size(); ++f) {
    const auto& t = ts[f];
    for (int i = 0; i < 3; ++i)
      if (t[i] >= vs.size())
        throw MeshShapeError("triangle " + std::to_string(f) + " indexes vertex " + std::to_string(t[i]) + " of " +
                             std::to_string(vs.size()));
    const dvec3 a = vs[t[0]], b = vs[t[1]], c = vs[t[2]];
    const dvec3 n = glm::cross(b - a, c - a);
    if (!(glm::length(n) > 0)) throw MeshShapeError("triangle " + std::to_string(f) + " has zero area");
    face_normal[f] = glm::normalize(n);
    volume6 += glm::dot(a, glm::cross(b, c));
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t from = t[i], to = t[(i + 1) % 3];
      if (!directed.emplace(std::pair{from, to}, f).second)
        throw MeshShapeError("edge " + edge_name(from, to) +
                             " is used twice in the same direction: non-manifold or inconsistently oriented");
      vertex_normal[t[i]] += corner_angle(vs[t[i]], vs[t[(i + 1) % 3]], vs[t[(i + 2) % 3]]) * face_normal[f];
    }
  }
  for (const auto& [edge, f] : directed)
    if (!directed.contains({edge.second, edge.first}))
      throw MeshShapeError("edge " + edge_name(edge.first, edge.second) +
                           " has no twin running the other way: the mesh is open or inconsistently oriented");
  if (!(volume6 > 0)) throw MeshShapeError("the mesh encloses a negative volume: it is inside out");

  // Median split on the longest axis of the centroids' box.
  std::vector<dvec3> centroid(ts.size());
  bounds_ = Box3{dvec3(INFINITY), dvec3(-INFINITY)};
  for (std::uint32_t f = 0; f < ts.size(); ++f) {
    centroid[f] = (vs[ts[f][0]] + vs[ts[f][1]] + vs[ts[f][2]]) / 3.0;
    for (int i = 0; i < 3; ++i) {
      bounds_.lo = glm::min(bounds_.lo, vs[ts[f][i]]);
      bounds_.hi = glm::max(bounds_.hi, vs[ts[f][i]]);
    }
  }
  order_.resize(ts.size());
  std::iota(order_.begin(), order_.end(), 0u);
  std::vector<Node<double>> nodes;
  auto build = [&](auto&& self, std::uint32_t first, std::uint32_t count) -> std::uint32_t {
    const auto index = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back({dvec3(INFINITY), dvec3(-INFINITY), first, 0, count});
    dvec3 clo(INFINITY), chi(-INFINITY);
    for (std::uint32_t i = first; i < first + count; ++i) {
      for (int k = 0; k < 3; ++k) {
        nodes[index].lo = glm::min(nodes[index].lo, vs[ts[order_[i]][k]]);
        nodes[index].hi = glm::max(nodes[index].hi, vs[ts[order_[i]][k]]);
      }
      clo = glm::min(clo, centroid[order_[i]]);
      chi = glm::max(chi, centroid[order_[i]]);
    }
    if (count <= kLeafSize) return index;
    const dvec3 extent = chi - clo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const std::uint32_t half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                     [&](std::uint32_t x, std::uint32_t y) { return centroid[x][axis] < centroid[y][axis]; });
    const std::uint32_t left = self(self, first, half);
    const std::uint32_t right = self(self, first + half, count - half);
    nodes[index].first = left;
    nodes[index].second = right;
    nodes[index].count = 0;
    return index;
  };
  build(build, 0, static_cast<std::uint32_t>(ts.size()));

  Arrays<double> d;
  d.nodes = std::move(nodes);
  for (const std::uint32_t f : order_) {
    const auto& t = ts[f];
    d.corners.push_back({vs[t[0]], vs[t[1]], vs[t[2]]});
    // An edge's pseudonormal: the sum of its two faces' normals (each weighted by the angle pi).
    auto edge = [&](int i) { return face_normal[f] + face_normal[directed.at({t[(i + 1) % 3], t[i]})]; };
    d.normals.push_back({vertex_normal[t[0]], vertex_normal[t[1]], vertex_normal[t[2]], edge(0), edge(1), edge(2),
                         face_normal[f]});
  }
  // Boxes rounded outwards, so a float query never prunes a box that holds its closest triangle.
  for (const auto& n : d.nodes) {
    glm::vec3 lo(n.lo), hi(n.hi);
    for (int i = 0; i < 3; ++i) {
      if (lo[i] > n.lo[i]) lo[i] = std::nextafter(lo[i], -INFINITY);
      if (hi[i] < n.hi[i]) hi[i] = std::nextafter(hi[i], INFINITY);
    }
    single_.nodes.push_back({lo, hi, n.first, n.second, n.count});
  }
  for (const auto& c : d.corners) single_.corners.push_back({glm::vec3(c[0]), glm::vec3(c[1]), glm::vec3(c[2])});
  for (const auto& n : d.normals) {
    std::array<glm::vec3, 7> f;
    for (size_t i = 0; i < 7; ++i) f[i] = glm::vec3(n[i]);
    single_.normals.push_back(f);
  }
  double_ = std::move(d);
}

}  // namespace marchcheck::sdf
