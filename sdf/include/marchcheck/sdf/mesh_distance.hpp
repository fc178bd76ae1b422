// A closed, consistently oriented triangle mesh as an exact signed distance field: the closest point through a
// bounding volume hierarchy, the sign from angle-weighted pseudonormals (Baerentzen & Aanaes 2005), which are
// right at edges and vertices, where the nearest face's own normal can point the wrong way.
#pragma once

#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/scalar.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace marchcheck::sdf {

// A mesh the distance field cannot take: empty, a bad index, a zero-area face, an edge without exactly one
// twin running the other way (open, non-manifold or inconsistently oriented), or inside out.
struct MeshShapeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class MeshDistance {
 public:
  // Throws MeshShapeError naming the problem.
  explicit MeshDistance(const TriangleMesh& mesh);

  const TriangleMesh& mesh() const { return mesh_; }
  const Box3& bounds() const { return bounds_; }

  // Which part of the closest triangle the closest point lies on: its vertex 0, 1, 2, its edge 01, 12, 20, or
  // its inside; each has its own pseudonormal.
  enum Feature : std::uint8_t { vertex0, vertex1, vertex2, edge01, edge12, edge20, face };

  template <class S>
  struct Closest {
    glm::vec<3, S> point;
    S distance2;
    std::uint32_t triangle;  // index into mesh().triangles
    Feature feature;
    glm::vec<3, S> pseudonormal;  // outward, not normalised
    glm::vec<3, S> face_normal;   // of the closest triangle, unit length
  };

  template <class S>
  Closest<S> closest(glm::vec<3, S> p) const;

  // Negative inside. T is float, double or Dual of them (the gradient is (p - closest) / distance, signed).
  template <class T>
  T signed_distance(glm::vec<3, T> p) const;

 private:
  template <class S>
  struct Node {
    glm::vec<3, S> lo, hi;
    std::uint32_t first;   // leaf: first triangle (BVH order); inner: left child
    std::uint32_t second;  // inner: right child
    std::uint32_t count;   // leaf: how many triangles; inner: 0
  };
  // Triangles in BVH order, each with its corners, its normal and the pseudonormals of its features.
  template <class S>
  struct Arrays {
    std::vector<std::array<glm::vec<3, S>, 3>> corners;
    std::vector<std::array<glm::vec<3, S>, 7>> normals;  // by Feature
    std::vector<Node<S>> nodes;
  };

  template <class S>
  const Arrays<S>& arrays() const {
    if constexpr (std::is_same_v<S, float>) {
      return single_;
    } else {
      return double_;
    }
  }

  TriangleMesh mesh_;
  Box3 bounds_;
  std::vector<std::uint32_t> order_;  // BVH position -> index in mesh_.triangles
  Arrays<float> single_;
  Arrays<double> double_;
};

namespace detail {

// Closest point of triangle abc to p and the feature it lies on (Ericson, Real-Time Collision Detection, 5.1.5,
// with the Voronoi region kept).
template <class S>
inline glm::vec<3, S> closest_on_triangle(glm::vec<3, S> p, const std::array<glm::vec<3, S>, 3>& t,
                                          MeshDistance::Feature& feature) {
  using V = glm::vec<3, S>;
  const V a = t[0], b = t[1], c = t[2];
  const V ab = b - a, ac = c - a, ap = p - a;
  const S d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  feature = MeshDistance::vertex0;
  if (d1 <= 0 && d2 <= 0) return a;
  const V bp = p - b;
  const S d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  feature = MeshDistance::vertex1;
  if (d3 >= 0 && d4 <= d3) return b;
  const S vc = d1 * d4 - d3 * d2;
  feature = MeshDistance::edge01;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const V cp = p - c;
  const S d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  feature = MeshDistance::vertex2;
  if (d6 >= 0 && d5 <= d6) return c;
  const S vb = d5 * d2 - d1 * d6;
  feature = MeshDistance::edge20;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const S va = d3 * d6 - d5 * d4;
  feature = MeshDistance::edge12;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  feature = MeshDistance::face;
  const S denom = S(1) / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

template <class S>
inline S box_distance2(glm::vec<3, S> p, glm::vec<3, S> lo, glm::vec<3, S> hi) {
  const glm::vec<3, S> d = glm::max(glm::max(lo - p, p - hi), glm::vec<3, S>(0));
  return glm::dot(d, d);
}

}  // namespace detail

template <class S>
MeshDistance::Closest<S> MeshDistance::closest(glm::vec<3, S> p) const {
  const Arrays<S>& a = arrays<S>();
  Closest<S> best{};
  best.distance2 = std::numeric_limits<S>::infinity();
  std::uint32_t best_slot = 0;
  // Nodes still to search with their boxes' distance2, kept so a node is pruned on popping without a second box
  // test; the nearer child is searched at once, the other waits on the stack.
  struct Pending {
    std::uint32_t node;
    S box2;
  };
  Pending stack[64];
  int top = 0;
  std::uint32_t at = 0;
  S at_box2 = detail::box_distance2(p, a.nodes[0].lo, a.nodes[0].hi);
  for (;;) {
    if (at_box2 < best.distance2) {
      const Node<S>& n = a.nodes[at];
      if (n.count == 0) {
        const S dl = detail::box_distance2(p, a.nodes[n.first].lo, a.nodes[n.first].hi);
        const S dr = detail::box_distance2(p, a.nodes[n.second].lo, a.nodes[n.second].hi);
        const bool left_first = dl < dr;
        stack[top++] = {left_first ? n.second : n.first, left_first ? dr : dl};
        at = left_first ? n.first : n.second;
        at_box2 = left_first ? dl : dr;
        continue;
      }
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
        Feature f;
        const glm::vec<3, S> q = detail::closest_on_triangle(p, a.corners[i], f);
        const glm::vec<3, S> d = p - q;
        const S d2 = glm::dot(d, d);
        if (d2 < best.distance2) {
          best.distance2 = d2;
          best.point = q;
          best.feature = f;
          best_slot = i;
        }
      }
    }
    if (top == 0) break;
    --top;
    at = stack[top].node;
    at_box2 = stack[top].box2;
  }
  best.triangle = order_[best_slot];
  best.pseudonormal = a.normals[best_slot][best.feature];
  best.face_normal = a.normals[best_slot][face];
  return best;
}

template <class T>
T MeshDistance::signed_distance(glm::vec<3, T> p) const {
  using S = decltype(value_of(T{}));
  const glm::vec<3, S> q(value_of(p.x), value_of(p.y), value_of(p.z));
  const Closest<S> c = closest(q);
  const S d = std::sqrt(c.distance2);
  const S sign = glm::dot(q - c.point, c.pseudonormal) < 0 ? S(-1) : S(1);
  if constexpr (is_dual<T>::value) {
    // On the surface the direction to the closest point vanishes; the pseudonormal stands in for it.
    const glm::vec<3, S> g = d > 0 ? (q - c.point) * (sign / d) : glm::normalize(c.pseudonormal);
    return T(sign * d, p.x.d * g.x + p.y.d * g.y + p.z.d * g.z);
  } else {
    return sign * d;
  }
}

}  // namespace marchcheck::sdf
