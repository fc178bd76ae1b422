// Closest point of a triangle to a point (Ericson, Real-Time Collision Detection, 5.1.5), with the Voronoi region
// it lies in kept: the one routine every mesh distance here uses, in float or double alike.
//
// Two changes to Ericson's arithmetic keep float right beside long thin triangles (test_mesh_node.cpp): the sides of
// the edges are edge functions ap . (n x ab) (TriangleFrame), not his va, vb, vc, products of dot products that
// cancel; and inside the face the point is p's projection on the plane, p - n (ap . n) / (n . n), not
// a + ab v + ac w. On a needle 300 long 100-400 from the origin his weights moved the point along the face by up
// to 0.3 and misjudged the edges' sides 4e-3 in, so a distance of 0.015 came out 0.13; now both err by about float
// rounding of |ap|.

#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace marchcheck::meshes {

// Which part of a triangle a closest point lies on: vertex 0, 1, 2, edge 01, 12, 20, or the inside.
enum TriangleFeature : std::uint8_t { vertex0, vertex1, vertex2, edge01, edge12, edge20, face };

// The triangle's normal (counter-clockwise, not unit length) as the cross product of the two edges at its largest
// angle, the corner opposite its longest edge: of the three pairs, the one that cancels least (the largest of the
// three sines), so a needle's normal is right to rounding where cross(ab, ac) across its sharp tip loses a factor of
// its aspect ratio. Ties take the first of ab, bc, ca.
template <class S>
inline glm::vec<3, S> face_normal(glm::vec<3, S> ab, glm::vec<3, S> ac, glm::vec<3, S> bc) {
  const S lab = glm::dot(ab, ab), lbc = glm::dot(bc, bc), lca = glm::dot(ac, ac);
  if (lab >= lbc && lab >= lca) return glm::cross(ac, bc);  // at c: (a - c) x (b - c)
  if (lbc >= lca) return glm::cross(ab, ac);                 // at a
  return glm::cross(ab, bc);                                 // at b: (c - b) x (a - b)
}

// What the region tests need of a triangle besides its edges: face_normal n, and in its plane across each edge
// toward the inside n x ab, ac x n, n x bc (each perpendicular to n, so computed without cancellation).
template <class S>
struct TriangleFrame {
  glm::vec<3, S> n, across_ab, across_ac, across_bc;
};
template <class S>
inline TriangleFrame<S> triangle_frame(glm::vec<3, S> ab, glm::vec<3, S> ac, glm::vec<3, S> bc) {
  const glm::vec<3, S> n = face_normal(ab, ac, bc);
  return {n, glm::cross(n, ab), glm::cross(ac, n), glm::cross(n, bc)};
}

template <class S>
inline glm::vec<3, S> closest_on_triangle(glm::vec<3, S> p, const std::array<glm::vec<3, S>, 3>& t,
                                          TriangleFeature& feature) {
  using V = glm::vec<3, S>;
  const V a = t[0], b = t[1], c = t[2];
  const V ab = b - a, ac = c - a, ap = p - a;
  const TriangleFrame<S> f = triangle_frame(ab, ac, V(c - b));
  const S d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  feature = vertex0;
  if (d1 <= 0 && d2 <= 0) return a;
  const V bp = p - b;
  const S d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  feature = vertex1;
  if (d3 >= 0 && d4 <= d3) return b;
  const S vc = glm::dot(ap, f.across_ab);  // c's side of ab
  feature = edge01;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const V cp = p - c;
  const S d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  feature = vertex2;
  if (d6 >= 0 && d5 <= d6) return c;
  const S vb = glm::dot(ap, f.across_ac);  // b's side of ac
  feature = edge20;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const S va = glm::dot(bp, f.across_bc);  // a's side of bc
  feature = edge12;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  feature = face;
  return p - f.n * (glm::dot(ap, f.n) / glm::dot(f.n, f.n));
}

}  // namespace marchcheck::meshes
