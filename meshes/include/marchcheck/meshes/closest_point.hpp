// Closest point of a triangle to a point (Ericson, Real-Time Collision Detection, 5.1.5), with the Voronoi region
// it lies in kept: the one routine every mesh distance here uses, in float, double or Dual arithmetic alike.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace marchcheck::meshes {

// Which part of a triangle a closest point lies on: vertex 0, 1, 2, edge 01, 12, 20, or the inside.
enum TriangleFeature : std::uint8_t { vertex0, vertex1, vertex2, edge01, edge12, edge20, face };

template <class S>
inline glm::vec<3, S> closest_on_triangle(glm::vec<3, S> p, const std::array<glm::vec<3, S>, 3>& t,
                                          TriangleFeature& feature) {
  using V = glm::vec<3, S>;
  const V a = t[0], b = t[1], c = t[2];
  const V ab = b - a, ac = c - a, ap = p - a;
  const S d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  feature = vertex0;
  if (d1 <= 0 && d2 <= 0) return a;
  const V bp = p - b;
  const S d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  feature = vertex1;
  if (d3 >= 0 && d4 <= d3) return b;
  const S vc = d1 * d4 - d3 * d2;
  feature = edge01;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const V cp = p - c;
  const S d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  feature = vertex2;
  if (d6 >= 0 && d5 <= d6) return c;
  const S vb = d5 * d2 - d1 * d6;
  feature = edge20;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const S va = d3 * d6 - d5 * d4;
  feature = edge12;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  feature = face;
  const S denom = S(1) / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace marchcheck::meshes
