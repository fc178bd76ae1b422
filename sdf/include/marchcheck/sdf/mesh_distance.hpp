// A closed, consistently oriented triangle mesh as an exact signed distance field: the closest point through a
// bounding volume hierarchy, the sign from angle-weighted pseudonormals (Baerentzen & Aanaes 2005), which are
// right at edges and vertices, where the nearest face's own normal can point the wrong way.
#pragma once

#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/closest_point.hpp"
#include "marchcheck/meshes/mesh.hpp"
#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/scalar.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace marchcheck::sdf {

// A mesh the distance field cannot take: a bad index, not a solid by meshes::solid_problem (empty, degenerate,
// open, non-manifold at an edge or a vertex, inconsistently oriented), or inside out.
struct MeshShapeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class MeshDistance {
 public:
  // Throws MeshShapeError naming the problem. note: what loading changed in the mesh (a weld), said to the user.
  explicit MeshDistance(const meshes::Mesh& mesh, std::string note = {});

  const meshes::Mesh& mesh() const { return mesh_; }
  // meshes::inspect(mesh()), kept so that a reference built for the same mesh need not inspect it again.
  const meshes::MeshReport& report() const { return report_; }
  const std::string& note() const { return note_; }
  const Box3& bounds() const { return bounds_; }

  // Which part of the closest triangle the closest point lies on; each has its own pseudonormal.
  using Feature = meshes::TriangleFeature;

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
  // closest(points[i]) for each i < n, for coherent points (a packet's neighbouring rays, a ray's next step): a
  // search starts from the leaf where the previous point's ended, when p lies within that point's distance of it,
  // so it begins with a bound near its answer and prunes most of the tree. The same distance2; on an exact tie
  // (triangles around a closest vertex or edge) possibly another of the tied triangles, which share the closest
  // point's feature and so its pseudonormal and sign.
  template <class S>
  void closest(const glm::vec<3, S>* points, Closest<S>* out, int n) const;

  // Negative inside. T is float, double or Dual of them (the gradient is (p - closest) / distance, signed).
  template <class T>
  T signed_distance(glm::vec<3, T> p) const;
  // signed_distance at (x[i], y[i], z[i]) for each i < n through the batched closest(); T is float or double.
  template <class T>
  void signed_distances(const T* x, const T* y, const T* z, T* out, int n) const;

  // The float search's triangles in its order: what a shader needs to find closest<float>'s squared distance
  // (sdf::glsl_map), its runs of kLeafWidth being the search's leaves.
  const std::vector<std::array<glm::vec3, 3>>& float_corners() const { return single_.corners; }

 private:
  // Up to kLeafWidth triangles side by side, each corner and edge vector as one array per axis, so their
  // distances are computed together; unused lanes repeat the last triangle.
  static constexpr int kLeafWidth = 8;
  template <class S>
  struct Leaf {
    std::array<S, kLeafWidth> a[3], b[3], c[3], ab[3], ac[3], bc[3];
    std::array<S, kLeafWidth> n[3], across_ab[3], across_ac[3], across_bc[3];  // meshes::TriangleFrame
    std::uint32_t first;  // BVH position of lane 0
    std::uint32_t count;  // lanes that are triangles of their own
  };
  // Four children's boxes side by side (per axis, then child), tested together. A child is an inner node, or a
  // leaf with kLeafBit set; an unused one has an empty box (lo = +inf), which is never nearer than any distance.
  static constexpr std::uint32_t kLeafBit = 1u << 31;
  template <class S>
  struct BvhNode {
    std::array<S, 4> lo[3], hi[3];
    std::array<std::uint32_t, 4> child;
  };
  // Triangles in BVH order, each with its corners, its normal and the pseudonormals of its features.
  template <class S>
  struct Arrays {
    std::vector<std::array<glm::vec<3, S>, 3>> corners;
    std::vector<std::array<glm::vec<3, S>, 7>> normals;  // by Feature
    std::vector<BvhNode<S>> nodes;                          // the root first
    std::vector<Leaf<S>> leaves;
  };
  template <class S>
  static Leaf<S> make_leaf(const std::vector<std::array<glm::vec<3, S>, 3>>& corners, std::uint32_t first,
                           std::uint32_t count);
  // The construction's stages: a binary tree by median splits, then collapsed to four-wide nodes in double and
  // in float.
  struct BinaryNode;
  std::uint32_t split(std::vector<BinaryNode>& binary, const std::vector<glm::dvec3>& centroids, std::uint32_t first,
                      std::uint32_t count);
  std::uint32_t collapse(const std::vector<BinaryNode>& binary, std::uint32_t at, bool root, Arrays<double>& d);

  // A search's result before the closest point is computed: the squared distance, the BVH position and the leaf.
  static constexpr std::uint32_t kNoLeaf = ~0u;
  template <class S>
  struct Found {
    S best2;
    std::uint32_t slot, leaf;
  };
  // The closest triangle to p, starting from leaf `start` (kNoLeaf: from the root alone).
  template <class S>
  Found<S> search(glm::vec<3, S> p, std::uint32_t start) const;
  // Takes those of leaf `index`'s triangles nearer than the best so far into `found`.
  template <class S>
  void take_leaf(glm::vec<3, S> p, std::uint32_t index, Found<S>& found) const;
  template <class S>
  Closest<S> closest_of(glm::vec<3, S> p, const Found<S>& found) const;
  // -1 where p lies inside by the closest point's pseudonormal, else 1.
  template <class S>
  static S outward_sign(glm::vec<3, S> p, const Closest<S>& c);

  template <class S>
  const Arrays<S>& arrays() const {
    if constexpr (std::is_same_v<S, float>) {
      return single_;
    } else {
      return double_;
    }
  }

  meshes::Mesh mesh_;
  meshes::MeshReport report_;
  std::string note_;
  Box3 bounds_;
  std::vector<std::uint32_t> order_;  // BVH position -> index in mesh_.triangles
  Arrays<float> single_;
  Arrays<double> double_;
};

namespace detail {

// A row of lanes as a GCC vector, so the compiler computes them in SIMD registers whatever it makes of a loop.
// Always inlined, so that no call passes a vector wider than the target's registers: GCC's warning that such a
// return changes the ABI (without -march=native) concerns calls that never happen (down to boxes_distance2).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <class S, std::size_t N>
[[gnu::always_inline]] inline auto lanes(const std::array<S, N>& a) {
  typedef S V __attribute__((vector_size(N * sizeof(S))));
  V v;
  std::memcpy(&v, a.data(), sizeof v);
  return v;
}

// (x, y, z) · across, lane by lane. Vectors by reference only: GCC checks a function's vector parameters and
// return at the end of the translation unit, outside this file's diagnostic pragma, and -Werror then fails a
// build without AVX over a call that is always inlined.
template <class V, class A>
[[gnu::always_inline]] inline void dot_lanes(const V& x, const V& y, const V& z, const A& across, V& out) {
  out = x * lanes(across[0]) + y * lanes(across[1]) + z * lanes(across[2]);
}

// Squared distance from p to each of a leaf's triangles, by closest_on_triangle's arithmetic operation for
// operation (so to the bit), with every candidate point computed and the one its branches would return chosen.
template <class S, class L>
inline void leaf_distance2(glm::vec<3, S> p, const L& l, S* out) {
  using V = decltype(lanes(l.a[0]));
  const V apx = p.x - lanes(l.a[0]), apy = p.y - lanes(l.a[1]), apz = p.z - lanes(l.a[2]);
  const V bpx = p.x - lanes(l.b[0]), bpy = p.y - lanes(l.b[1]), bpz = p.z - lanes(l.b[2]);
  const V cpx = p.x - lanes(l.c[0]), cpy = p.y - lanes(l.c[1]), cpz = p.z - lanes(l.c[2]);
  const V abx = lanes(l.ab[0]), aby = lanes(l.ab[1]), abz = lanes(l.ab[2]);
  const V acx = lanes(l.ac[0]), acy = lanes(l.ac[1]), acz = lanes(l.ac[2]);
  const V d1 = abx * apx + aby * apy + abz * apz, d2 = acx * apx + acy * apy + acz * apz;
  const V d3 = abx * bpx + aby * bpy + abz * bpz, d4 = acx * bpx + acy * bpy + acz * bpz;
  const V d5 = abx * cpx + aby * cpy + abz * cpz, d6 = acx * cpx + acy * cpy + acz * cpz;
  V vc, vb, va;
  dot_lanes(apx, apy, apz, l.across_ab, vc);
  dot_lanes(apx, apy, apz, l.across_ac, vb);
  dot_lanes(bpx, bpy, bpz, l.across_bc, va);
  const V t01 = d1 / (d1 - d3), t20 = d2 / (d2 - d6), t12 = (d4 - d3) / ((d4 - d3) + (d5 - d6));
  const V nx = lanes(l.n[0]), ny = lanes(l.n[1]), nz = lanes(l.n[2]);
  // p's height over each plane, in units of |n|.
  const V plane = (apx * nx + apy * ny + apz * nz) / (nx * nx + ny * ny + nz * nz);
  const auto v0 = (d1 <= 0) & (d2 <= 0), v1 = (d3 >= 0) & (d4 <= d3), e01 = (vc <= 0) & (d1 >= 0) & (d3 <= 0);
  const auto v2 = (d6 >= 0) & (d5 <= d6), e20 = (vb <= 0) & (d2 >= 0) & (d6 <= 0);
  const auto e12 = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0);
  V d[3];
  for (int i = 0; i < 3; ++i) {
    const V a = lanes(l.a[i]), b = lanes(l.b[i]), ab = lanes(l.ab[i]), ac = lanes(l.ac[i]);
    V q = p[i] - lanes(l.n[i]) * plane;
    q = e12 ? b + lanes(l.bc[i]) * t12 : q;
    q = e20 ? a + ac * t20 : q;
    q = v2 ? lanes(l.c[i]) : q;
    q = e01 ? a + ab * t01 : q;
    q = v1 ? b : q;
    q = v0 ? a : q;
    d[i] = p[i] - q;
  }
  const V d2sum = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  std::memcpy(out, &d2sum, sizeof d2sum);
}

// Squared distance from p to each of four boxes.
template <class S>
inline void boxes_distance2(glm::vec<3, S> p, const std::array<S, 4> (&lo)[3], const std::array<S, 4> (&hi)[3],
                            S* out) {
  using V = decltype(lanes(lo[0]));
  V sum{};
  for (int i = 0; i < 3; ++i) {
    const V below = lanes(lo[i]) - p[i], above = p[i] - lanes(hi[i]);
    V d = below > above ? below : above;
    d = d < 0 ? V{} : d;  // NaN stays NaN (a point with a NaN coordinate searches nothing)
    sum = i == 0 ? d * d : sum + d * d;
  }
  std::memcpy(out, &sum, sizeof sum);
}
#pragma GCC diagnostic pop

}  // namespace detail

template <class S>
void MeshDistance::take_leaf(glm::vec<3, S> p, std::uint32_t index, Found<S>& found) const {
  const Leaf<S>& l = arrays<S>().leaves[index];
  S d2[kLeafWidth];
  detail::leaf_distance2(p, l, d2);
  for (std::uint32_t k = 0; k < l.count; ++k)
    if (d2[k] < found.best2) {
      found.best2 = d2[k];
      found.slot = l.first + k;
      found.leaf = index;
    }
}

template <class S>
MeshDistance::Found<S> MeshDistance::search(glm::vec<3, S> p, std::uint32_t start) const {
  const Arrays<S>& a = arrays<S>();
  Found<S> found{std::numeric_limits<S>::infinity(), 0, kNoLeaf};
  if (start != kNoLeaf) take_leaf(p, start, found);
  // Nodes still to search with their boxes' distance2, pruned on popping against the best found by then; the
  // nearest child is searched at once, the others wait on the stack, nearer ones on top. The collapsed median
  // tree is at most 32 levels deep, with three waiting per level.
  struct Pending {
    std::uint32_t node;
    S box2;
  };
  Pending stack[96];
  int top = 0;
  std::uint32_t at = 0;
  for (;;) {
    if (at & kLeafBit) {
      if ((at & ~kLeafBit) != start) take_leaf(p, at & ~kLeafBit, found);
    } else {
      const BvhNode<S>& n = a.nodes[at];
      S box2[4];
      detail::boxes_distance2(p, n.lo, n.hi, box2);
      // The children nearer than the best, nearest first.
      int near[4], count = 0;
      for (int k = 0; k < 4; ++k) {
        if (!(box2[k] < found.best2)) continue;
        int j = count++;
        for (; j > 0 && box2[near[j - 1]] > box2[k]; --j) near[j] = near[j - 1];
        near[j] = k;
      }
      if (count > 0) {
        for (int j = count - 1; j > 0; --j) stack[top++] = {n.child[near[j]], box2[near[j]]};
        at = n.child[near[0]];
        continue;
      }
    }
    while (top > 0 && !(stack[top - 1].box2 < found.best2)) --top;
    if (top == 0) break;
    at = stack[--top].node;
  }
  return found;
}

template <class S>
MeshDistance::Closest<S> MeshDistance::closest_of(glm::vec<3, S> p, const Found<S>& found) const {
  const Arrays<S>& a = arrays<S>();
  Closest<S> best;
  best.point = meshes::closest_on_triangle(p, a.corners[found.slot], best.feature);
  // Where no triangle was found (a point with a NaN coordinate, or so far that every distance overflows), the
  // distance to triangle 0's point: NaN or +inf, never a finite number.
  best.distance2 = found.leaf == kNoLeaf ? glm::dot(p - best.point, p - best.point) : found.best2;
  best.triangle = order_[found.slot];
  best.pseudonormal = a.normals[found.slot][best.feature];
  best.face_normal = a.normals[found.slot][meshes::face];
  return best;
}

template <class S>
MeshDistance::Closest<S> MeshDistance::closest(glm::vec<3, S> p) const {
  return closest_of(p, search(p, kNoLeaf));
}

template <class S>
void MeshDistance::closest(const glm::vec<3, S>* points, Closest<S>* out, int n) const {
  Found<S> previous{0, 0, kNoLeaf};
  for (int i = 0; i < n; ++i) {
    const glm::vec<3, S> p = points[i], step = i > 0 ? p - points[i - 1] : glm::vec<3, S>(0);
    // Within the previous point's distance, that point's closest triangle lies within twice that distance of p: a
    // bound worth starting from. NaN compares false: from the root.
    const bool near = previous.leaf != kNoLeaf && glm::dot(step, step) <= previous.best2;
    previous = search(p, near ? previous.leaf : kNoLeaf);
    out[i] = closest_of(p, previous);
  }
}

template <class S>
S MeshDistance::outward_sign(glm::vec<3, S> p, const Closest<S>& c) {
  return glm::dot(p - c.point, c.pseudonormal) < 0 ? S(-1) : S(1);
}

template <class T>
T MeshDistance::signed_distance(glm::vec<3, T> p) const {
  using S = decltype(value_of(T{}));
  const glm::vec<3, S> q(value_of(p.x), value_of(p.y), value_of(p.z));
  const Closest<S> c = closest(q);
  const S d = std::sqrt(c.distance2), sign = outward_sign(q, c);
  if constexpr (is_dual<T>::value) {
    // On the surface the direction to the closest point vanishes; the pseudonormal stands in for it.
    const glm::vec<3, S> g = d > 0 ? (q - c.point) * (sign / d) : glm::normalize(c.pseudonormal);
    return T(sign * d, p.x.d * g.x + p.y.d * g.y + p.z.d * g.z);
  } else {
    return sign * d;
  }
}

template <class T>
void MeshDistance::signed_distances(const T* x, const T* y, const T* z, T* out, int n) const {
  constexpr int kChunk = 64;  // points per batched search, on the stack
  glm::vec<3, T> points[kChunk];
  Closest<T> found[kChunk];
  for (int base = 0; base < n; base += kChunk) {
    const int m = std::min(kChunk, n - base);
    for (int i = 0; i < m; ++i) points[i] = {x[base + i], y[base + i], z[base + i]};
    closest(points, found, m);
    for (int i = 0; i < m; ++i) out[base + i] = outward_sign(points[i], found[i]) * std::sqrt(found[i].distance2);
  }
}

}  // namespace marchcheck::sdf
