// Independent geometry for the mesh tests: brute-force distances and face sampling (no code shared with meshes/).
#pragma once

#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/mesh.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace marchcheck::meshes::test {

using glm::dvec3;

inline double segment_distance(dvec3 p, dvec3 a, dvec3 b) {
  const dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double s = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + s * ab));
}

// Inside the prism over the triangle: the distance to its plane; outside: the nearest edge.
inline double triangle_distance(dvec3 p, dvec3 a, dvec3 b, dvec3 c) {
  const dvec3 n = glm::cross(b - a, c - a);
  const double n2 = glm::dot(n, n);
  if (n2 > 0) {
    const bool inside = glm::dot(glm::cross(b - a, p - a), n) >= 0 && glm::dot(glm::cross(c - b, p - b), n) >= 0 &&
                        glm::dot(glm::cross(a - c, p - c), n) >= 0;
    if (inside) return std::fabs(glm::dot(p - a, n)) / std::sqrt(n2);
  }
  return std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

inline double mesh_distance(const Mesh& mesh, dvec3 p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles)
    best = std::min(best, triangle_distance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
  return best;
}

// Barycentric grid with n steps per edge: corners, edge points and interior points of every face.
inline void for_each_face_sample(const Mesh& mesh, int n, const std::function<void(dvec3)>& visit) {
  for (const auto& t : mesh.triangles) {
    const dvec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = double(i) / n, v = double(j) / n;
        visit(a + u * (b - a) + v * (c - a));
      }
  }
}

// Unsigned distances to the analytic surfaces, written from their definitions.
inline double sphere_distance(dvec3 p, double radius) { return std::fabs(glm::length(p) - radius); }
inline double torus_distance(dvec3 p, double major, double minor) {
  return std::fabs(std::hypot(std::hypot(p.x, p.z) - major, p.y) - minor);
}
inline double box_distance(dvec3 p, dvec3 half) {
  const dvec3 q = glm::abs(p) - half;
  const double outside = glm::length(glm::max(q, dvec3(0)));
  return std::fabs(outside + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0));
}

// Two cones of n sides meeting tip to tip at the origin (bases at y = +-1, radius 1), outward: every edge has two
// faces, but the tip is one vertex with two fans, so the mesh is closed yet pinched (not manifold there).
inline Mesh pinched_double_cone(int n = 16) {
  Mesh m;
  m.vertices.push_back(dvec3(0));  // the shared tip
  for (const double y : {1.0, -1.0}) {
    const auto centre = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(dvec3(0, y, 0));
    for (int i = 0; i < n; ++i) {
      const double a = 2 * 3.14159265358979323846 * i / n;
      m.vertices.push_back(dvec3(std::cos(a), y, std::sin(a)));
    }
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
      const std::uint32_t r0 = centre + 1 + i, r1 = centre + 1 + (i + 1) % static_cast<std::uint32_t>(n);
      // Counter-clockwise seen from outside: the upper cone's base faces +y, the lower's -y.
      if (y > 0) {
        m.triangles.push_back({centre, r1, r0});
        m.triangles.push_back({0, r0, r1});
      } else {
        m.triangles.push_back({centre, r0, r1});
        m.triangles.push_back({0, r1, r0});
      }
    }
  }
  return m;
}

// A CAD-like plate 300 x 200 x 3 with its corner at (100, 100, 100): its top and bottom are fans from that corner
// to the far edges, split at `needles` points along the edge x = 400, so all but the last triangle of each fan are
// needles about 300 long and 200 / needles wide at their far end (aspect about 1.5 needles); its sides are strips.
inline Mesh sliver_plate(int needles = 200) {
  std::vector<dvec3> ring = {{100, 100, 0}, {400, 100, 0}};
  for (int k = 1; k <= needles; ++k) ring.push_back({400, 100 + 200.0 * k / needles, 0});
  ring.push_back({100, 300, 0});
  Mesh m;
  const auto n = static_cast<std::uint32_t>(ring.size());
  for (const double z : {100.0, 103.0})
    for (const dvec3& v : ring) m.vertices.push_back({v.x, v.y, z});
  for (std::uint32_t i = 1; i + 1 < n; ++i) {
    m.triangles.push_back({0, i + 1, i});              // bottom, facing -z
    m.triangles.push_back({n, n + i, n + i + 1});      // top, facing +z
  }
  for (std::uint32_t i = 0; i < n; ++i) {  // sides: the ring runs counter-clockwise seen from +z
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({i, j, n + j});
    m.triangles.push_back({i, n + j, n + i});
  }
  return m;
}

// Every mesh check clean: closed, manifold, outward, no degenerate faces or duplicate vertices.
inline void expect_clean(const MeshReport& r) {
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_TRUE(r.outward);
  EXPECT_EQ(r.boundary_edges, 0);
  EXPECT_EQ(r.nonmanifold_edges, 0);
  EXPECT_EQ(r.nonmanifold_vertices, 0);
  EXPECT_EQ(r.degenerate_faces, 0);
  EXPECT_EQ(r.duplicate_vertices, 0);
}

}  // namespace marchcheck::meshes::test
