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
#include "marchcheck/sdf/vector_width.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
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
  // search starts from the leaf where the previous point's ended, when p lies within that point's distance of it
  // (else as closest(p) starts), so it begins with a bound near its answer and prunes most of the tree. The same
  // answer as closest(p), bit for bit: wherever a search starts, it returns the nearest triangle first in BVH order.
  template <class S>
  void closest(const glm::vec<3, S>* points, Closest<S>* out, int n) const;

  // How many leaves (up to 16 triangles each) closest(p) searches: its cost, as deterministic as a march's
  // evaluations, and what the bounds of the tree's boxes and the start grid decide.
  template <class S>
  int leaves_searched(glm::vec<3, S> p) const {
    return static_cast<int>(search(p, start_leaf(p)).leaves);
  }

  // Negative inside. T is float, double or Dual of them (the gradient is (p - closest) / distance, signed).
  template <class T>
  T signed_distance(glm::vec<3, T> p) const;
  // signed_distance at (x[i], y[i], z[i]) for each i < n through the batched closest(); T is float or double.
  template <class T>
  void signed_distances(const T* x, const T* y, const T* z, T* out, int n) const;

  // The float search's triangles in its order: what a shader needs to find closest<float>'s squared distance
  // (sdf::glsl_map); runs of 16 are the search's leaves, of 8 the shader's.
  const std::vector<std::array<glm::vec3, 3>>& float_corners() const { return single_.corners; }

 private:
  // Up to kLeafWidth triangles side by side, each corner and face normal (meshes::face_normal) as one array per
  // axis, so their distances are computed together (16 lanes: one AVX-512 register of floats); unused lanes
  // repeat the last triangle. The edges and their normals are computed from these where needed, as
  // closest_on_triangle computes them (so to the bit): 48 bytes a float triangle instead of 120.
  static constexpr int kLeafWidth = 16;
  template <class S>
  struct alignas(64) Leaf {
    std::array<S, kLeafWidth> a[3], b[3], c[3], n[3];
  };
  // kNodeWidth children's bounds side by side (per axis, then child), tested together: 8 floats, one AVX register,
  // so a search reads two thirds of the nodes a four-wide tree makes it read (measured 11.1 against 16.5 a point on
  // an 86k-triangle torus), at one vector operation each. A child is an inner node, or a
  // leaf with kLeafBit set; an unused one has NaN bounds, so a NaN distance, which is never searched.
  // Each child has an axis-aligned box and an oriented one (a centre, three unit axes, half extents along them)
  // about its triangles' mean plane: on a curved surface's patch, or one askew to the axes, the oriented box is
  // far the tighter: with it a search read half (torus) to a third (icosphere) of the leaves it read with the
  // axis-aligned boxes alone (measured from the root at random points: MeshNode.OrientedBoxesKeep...).
  static constexpr std::uint32_t kLeafBit = 1u << 31;
  static constexpr int kNodeWidth = 8;
  template <class S>
  struct BvhNode {
    std::array<S, kNodeWidth> lo[3], hi[3];
    std::array<S, kNodeWidth> centre[3], axes[3][3], half[3];  // axes[r][i]: axis r's component i
    std::array<std::uint32_t, kNodeWidth> child;
  };
  // Triangles in BVH order, each with its corners, its normal and the pseudonormals of its features.
  template <class S>
  struct Arrays {
    std::vector<std::array<glm::vec<3, S>, 3>> corners;
    std::vector<std::array<glm::vec<3, S>, 7>> normals;  // by Feature
    std::vector<BvhNode<S>> nodes;                          // the root first
    std::vector<Leaf<S>> leaves;
    std::vector<std::uint32_t> leaf_first;  // BVH position of each leaf's lane 0
  };
  template <class S>
  static void add_leaf(Arrays<S>& arrays, std::uint32_t first, std::uint32_t count);
  template <class S>
  static void set_oriented_box(BvhNode<S>& node, int k, const std::array<glm::dvec3, 3>& axes,
                               const std::vector<std::array<glm::dvec3, 3>>& corners, std::uint32_t begin,
                               std::uint32_t end);
  // The construction's stages: a binary tree by median splits, then collapsed to kNodeWidth-wide nodes in double
  // and in float.
  struct BinaryNode;
  std::uint32_t split(std::vector<BinaryNode>& binary, const std::vector<glm::dvec3>& centroids, std::uint32_t first,
                      std::uint32_t count);
  std::uint32_t collapse(const std::vector<BinaryNode>& binary, std::uint32_t at, bool root, Arrays<double>& d);

  // A search's result before the closest point is computed: the squared distance, the BVH position and the leaf.
  static constexpr std::uint32_t kNoLeaf = ~0u;
  template <class S>
  struct Found {
    S best2;
    std::uint32_t slot, leaf, lane;
    std::uint32_t leaves;  // searched
  };
  // Where a search with no neighbour to start from begins: the leaf holding the triangle nearest the centre of p's
  // cell in a grid over the mesh's box (p clamped into it). A start near the answer bounds the search at once: at
  // random points about an 86k-triangle torus it reads 14% fewer leaves than one from the root alone. kNoLeaf for a
  // NaN coordinate, or where the mesh has too few leaves for a grid.
  template <class S>
  std::uint32_t start_leaf(glm::vec<3, S> p) const;
  void build_start_grid();
  // The closest triangle to p, starting from leaf `start` (kNoLeaf: from the root alone).
  template <class S>
  Found<S> search(glm::vec<3, S> p, std::uint32_t start) const;
  // Fetches a node or leaf (kLeafBit) into the cache ahead of its search.
  template <class S>
  void prefetch(std::uint32_t id) const;
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
  int start_cells_ = 0;                // per axis; 0: no grid
  glm::vec3 start_origin_{0}, start_cells_per_unit_{0};
  std::vector<std::uint32_t> start_leaves_;  // by cell, x fastest
  Arrays<float> single_;
  Arrays<double> double_;
};

namespace detail {

// A row of lanes as a GCC vector, so the compiler computes them in SIMD registers whatever it makes of a loop.
// Always inlined, so that no call passes a vector wider than the target's registers: GCC's warning that such a
// return changes the ABI (without -march=native) concerns calls that never happen (down to bounds_distance2).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <std::size_t N, class S>
[[gnu::always_inline]] inline auto lanes(const S* a) {
  typedef S V __attribute__((vector_size(N * sizeof(S))));
  V v;
  std::memcpy(&v, a, sizeof v);
  return v;
}

// leaf_distance2 for lanes [at, at + N) of leaf l.
template <std::size_t N, class S, class L>
inline void leaf_row_distance2(glm::vec<3, S> p, const L& l, std::size_t at, S* out) {
  using V = decltype(lanes<N>(l.a[0].data()));
  const V ax = lanes<N>(l.a[0].data() + at), ay = lanes<N>(l.a[1].data() + at), az = lanes<N>(l.a[2].data() + at);
  const V bx = lanes<N>(l.b[0].data() + at), by = lanes<N>(l.b[1].data() + at), bz = lanes<N>(l.b[2].data() + at);
  const V cx = lanes<N>(l.c[0].data() + at), cy = lanes<N>(l.c[1].data() + at), cz = lanes<N>(l.c[2].data() + at);
  const V nx = lanes<N>(l.n[0].data() + at), ny = lanes<N>(l.n[1].data() + at), nz = lanes<N>(l.n[2].data() + at);
  const V abx = bx - ax, aby = by - ay, abz = bz - az;
  const V acx = cx - ax, acy = cy - ay, acz = cz - az;
  const V bcx = cx - bx, bcy = cy - by, bcz = cz - bz;
  const V apx = p.x - ax, apy = p.y - ay, apz = p.z - az;
  const V bpx = p.x - bx, bpy = p.y - by, bpz = p.z - bz;
  const V cpx = p.x - cx, cpy = p.y - cy, cpz = p.z - cz;
  const V d1 = abx * apx + aby * apy + abz * apz, d2 = acx * apx + acy * apy + acz * apz;
  const V d3 = abx * bpx + aby * bpy + abz * bpz, d4 = acx * bpx + acy * bpy + acz * bpz;
  const V d5 = abx * cpx + aby * cpy + abz * cpz, d6 = acx * cpx + acy * cpy + acz * cpz;
  // The edge functions with meshes::triangle_frame's n x ab, ac x n and n x bc, as glm::cross computes them.
  const V vc = apx * (ny * abz - aby * nz) + apy * (nz * abx - abz * nx) + apz * (nx * aby - abx * ny);
  const V vb = apx * (acy * nz - ny * acz) + apy * (acz * nx - nz * acx) + apz * (acx * ny - nx * acy);
  const V va = bpx * (ny * bcz - bcy * nz) + bpy * (nz * bcx - bcz * nx) + bpz * (nx * bcy - bcx * ny);
  const V t01 = d1 / (d1 - d3), t20 = d2 / (d2 - d6), t12 = (d4 - d3) / ((d4 - d3) + (d5 - d6));
  // p's height over each plane, in units of |n|.
  const V plane = (apx * nx + apy * ny + apz * nz) / (nx * nx + ny * ny + nz * nz);
  const auto v0 = (d1 <= 0) & (d2 <= 0), v1 = (d3 >= 0) & (d4 <= d3), e01 = (vc <= 0) & (d1 >= 0) & (d3 <= 0);
  const auto v2 = (d6 >= 0) & (d5 <= d6), e20 = (vb <= 0) & (d2 >= 0) & (d6 <= 0);
  const auto e12 = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0);
  const V a[3] = {ax, ay, az}, b[3] = {bx, by, bz}, c[3] = {cx, cy, cz}, n[3] = {nx, ny, nz};
  const V ab[3] = {abx, aby, abz}, ac[3] = {acx, acy, acz}, bc[3] = {bcx, bcy, bcz};
  V d[3];
  for (int i = 0; i < 3; ++i) {
    V q = p[i] - n[i] * plane;
    q = e12 ? b[i] + bc[i] * t12 : q;
    q = e20 ? a[i] + ac[i] * t20 : q;
    q = v2 ? c[i] : q;
    q = e01 ? a[i] + ab[i] * t01 : q;
    q = v1 ? b[i] : q;
    q = v0 ? a[i] : q;
    d[i] = p[i] - q;
  }
  const V d2sum = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  std::memcpy(out, &d2sum, sizeof d2sum);
}

// How many of a leaf's lanes are computed as one vector: a row as wide as the target's vector registers (rows of
// 64 bytes on AVX2 spilled the leaf's values out of its sixteen registers: 0.18 M queries/s on the torus, against
// 0.68 M), and at most 64 bytes (16 floats, 8 doubles), as clang 14 cannot split a row of 16 doubles under
// -frounding-math (a backend crash in the fuzz build).
template <class S>
constexpr std::size_t row_lanes(std::size_t lanes) {
  return std::min(lanes, std::size_t{kVectorBytes} / sizeof(S));
}

// Squared distance from p to each of a leaf's triangles, by closest_on_triangle's arithmetic operation for
// operation (so to the bit), with every candidate point computed and the one its branches would return chosen.
template <class S, class L>
inline void leaf_distance2(glm::vec<3, S> p, const L& l, S* out) {
  constexpr std::size_t kLanes = sizeof(l.a[0]) / sizeof(S);
  constexpr std::size_t kRow = row_lanes<S>(kLanes);
  for (std::size_t at = 0; at < kLanes; at += kRow) leaf_row_distance2<kRow>(p, l, at, out + at);
}

// A lower bound on the squared distance from p to each of a node's children: the larger of the squared
// distances to its axis-aligned box and to its oriented box. The oriented one is computed in S and lowered by what
// rounding can add to it: p's coordinates along an axis ((p - centre) . axis) err by at most 4 roundoffs of
// |p - centre|'s L1 norm (a subtraction and a three-term dot product; an axis's components are at most 1), taken
// off 32 times over; the axes, unit vectors rounded to S, are orthonormal to a few roundoffs, so the sum of
// squares is scaled down by 64 of them.
template <class S, class Node>
inline void bounds_distance2(glm::vec<3, S> p, const Node& node, S* out) {
  constexpr std::size_t kWidth = sizeof(node.lo[0]) / sizeof(S);
  using V = decltype(lanes<kWidth>(node.lo[0].data()));
  constexpr S kRoundoff = std::numeric_limits<S>::epsilon() / 2;
  V box{};
  for (int i = 0; i < 3; ++i) {
    const V below = lanes<kWidth>(node.lo[i].data()) - p[i], above = p[i] - lanes<kWidth>(node.hi[i].data());
    V d = below > above ? below : above;
    d = d < 0 ? V{} : d;  // NaN stays NaN (a point with a NaN coordinate searches nothing)
    box = i == 0 ? d * d : box + d * d;
  }
  const V x = p.x - lanes<kWidth>(node.centre[0].data());
  const V y = p.y - lanes<kWidth>(node.centre[1].data());
  const V z = p.z - lanes<kWidth>(node.centre[2].data());
  const V slack = (32 * 4 * kRoundoff) * ((x < 0 ? -x : x) + (y < 0 ? -y : y) + (z < 0 ? -z : z));
  V oriented{};
  for (int r = 0; r < 3; ++r) {
    const auto& axis = node.axes[r];
    V along = x * lanes<kWidth>(axis[0].data()) + y * lanes<kWidth>(axis[1].data()) + z * lanes<kWidth>(axis[2].data());
    along = (along < 0 ? -along : along) - lanes<kWidth>(node.half[r].data()) - slack;
    along = along < 0 ? V{} : along;
    oriented = r == 0 ? along * along : oriented + along * along;
  }
  oriented *= 1 - 64 * kRoundoff;
  // A NaN box distance stays NaN whatever the oriented box's.
  const V bound = oriented > box ? oriented : box;
  std::memcpy(out, &bound, sizeof bound);
}

// One stage of a bitonic sorting network on N lanes (blocks of K, pairs J apart), then the stages after it; the
// shuffle and the choice of the smaller or larger are constants, made at compile time (__builtin_shufflevector:
// GCC and clang alike, as the fuzz build compiles this with clang).
template <std::size_t N, std::size_t K, std::size_t J, class Key, class Mask>
[[gnu::always_inline]] inline void bitonic_stages(Key& key) {
  // By reference, not by value: a vector wider than the baseline's registers passed or returned by value changes
  // the ABI, which GCC reports (-Wpsabi) at the end of every translation unit a portable build compiles.
  using I = std::remove_cvref_t<decltype(Mask{}[0])>;
  Key other;
  Mask smaller;
  [&]<std::size_t... L>(std::index_sequence<L...>) {
    other = __builtin_shufflevector(key, key, (L ^ J)...);
    smaller = Mask{static_cast<I>(((L & J) == 0) == ((L & K) == 0) ? -1 : 0)...};
  }(std::make_index_sequence<N>{});
  key = smaller ? (key < other ? key : other) : (key < other ? other : key);
  if constexpr (J > 1) {
    bitonic_stages<N, K, J / 2, Key, Mask>(key);
  } else if constexpr (K < N) {
    bitonic_stages<N, 2 * K, K, Key, Mask>(key);
  }
}

// Lanes 0..N-1 (a power of two) ordered by their values, the least first: a bitonic sorting network on keys that hold
// a value's bits above its lane (non-negative floats and doubles order as their bits, NaN after +inf), so without a
// branch on the data. The lane takes the value's lowest bits: values within a few units in the last place order by
// lane, which only orders the search, never prunes it.
template <std::size_t N, class S>
[[gnu::always_inline]] inline void nearest_first(const S* values, std::uint32_t* order) {
  using U = std::conditional_t<sizeof(S) == 4, std::uint32_t, std::uint64_t>;
  typedef U Key __attribute__((vector_size(N * sizeof(U))));
  typedef std::make_signed_t<U> I;
  typedef I Mask __attribute__((vector_size(N * sizeof(U))));
  static_assert(N >= 2 && (N & (N - 1)) == 0);
  constexpr U kLaneMask = N - 1;
  Key key;
  std::memcpy(&key, values, sizeof key);
  [&]<std::size_t... L>(std::index_sequence<L...>) {
    key = (key & ~kLaneMask) | Key{static_cast<U>(L)...};
  }(std::make_index_sequence<N>{});
  bitonic_stages<N, 2, 1, Key, Mask>(key);
  for (std::size_t i = 0; i < N; ++i) order[i] = static_cast<std::uint32_t>(key[i] & kLaneMask);
}

// Every one of N lanes made the least of them, the halves folded onto each other (J lanes apart, then J / 2...).
template <std::size_t N, std::size_t J, class V>
[[gnu::always_inline]] inline void fold_least(V& v) {
  V other;
  [&]<std::size_t... L>(std::index_sequence<L...>) {
    other = __builtin_shufflevector(v, v, (L ^ J)...);
  }(std::make_index_sequence<N>{});
  v = other < v ? other : v;
  if constexpr (J > 1) fold_least<N, J / 2>(v);
}

// The least of N values (NaN never least: +inf where all are) and the first lane holding it (N where none does),
// without a branch on the data: lanes equal to the least keep their index, the others N, and the least index is the
// first. Folding halves takes log2 N dependent steps where a running minimum takes N (a fifth of a leaf's time).
template <std::size_t N, class S>
[[gnu::always_inline]] inline S least_lane(const S* values, std::uint32_t& lane) {
  constexpr std::size_t kRow = row_lanes<S>(N);
  using V = decltype(lanes<kRow>(values));
  using U = std::conditional_t<sizeof(S) == 4, std::uint32_t, std::uint64_t>;
  typedef U Index __attribute__((vector_size(kRow * sizeof(U))));
  V least = V{} + std::numeric_limits<S>::infinity();
  for (std::size_t at = 0; at < N; at += kRow) {
    const V v = lanes<kRow>(values + at);
    least = v < least ? v : least;
  }
  fold_least<kRow, kRow / 2>(least);
  Index first = Index{} + static_cast<U>(N), index;
  [&]<std::size_t... L>(std::index_sequence<L...>) { index = Index{static_cast<U>(L)...}; }(
      std::make_index_sequence<kRow>{});
  for (std::size_t at = 0; at < N; at += kRow) {
    const V v = lanes<kRow>(values + at);
    const Index lane_at = index + static_cast<U>(at);
    first = ((v == least) & (lane_at < first)) ? lane_at : first;
  }
  fold_least<kRow, kRow / 2>(first);
  lane = static_cast<std::uint32_t>(first[0]);
  return least[0];
}
#pragma GCC diagnostic pop

}  // namespace detail

template <class S>
void MeshDistance::take_leaf(glm::vec<3, S> p, std::uint32_t index, Found<S>& found) const {
  const Leaf<S>& l = arrays<S>().leaves[index];
  S d2[kLeafWidth];
  detail::leaf_distance2(p, l, d2);
  ++found.leaves;
  // The nearest, the first in BVH order among exact ties (triangles about a closest vertex or edge), so that the
  // answer does not depend on where the search started: tied triangles compute the closest point, and so the sign
  // of a point within rounding of the surface, each in its own way. The least of the lanes (NaN lanes never
  // least), then its first lane: lanes are in BVH order, and one repeating the last triangle ties with it and comes
  // after it.
  const std::uint32_t before = found.slot, first = arrays<S>().leaf_first[index];
  std::uint32_t k;
  const S least = detail::least_lane<kLeafWidth>(d2, k);
  if (least <= found.best2) {
    if (k < kLeafWidth && (least < found.best2 || first + k < found.slot)) {
      found.best2 = least;
      found.slot = first + k;
      found.leaf = index;
      found.lane = k;
    }
  }
  // What closest_of will read of the nearest so far, fetched while the search goes on (a cache miss each, a fifth
  // of a query's time when waited for at the end).
  if (found.slot != before) {
    __builtin_prefetch(&order_[found.slot]);
    const char* normals = reinterpret_cast<const char*>(&arrays<S>().normals[found.slot]);
    __builtin_prefetch(normals);
    __builtin_prefetch(normals + sizeof(arrays<S>().normals[0]) - 1);
  }
}

template <class S>
MeshDistance::Found<S> MeshDistance::search(glm::vec<3, S> p, std::uint32_t start) const {
  const Arrays<S>& a = arrays<S>();
  Found<S> found{std::numeric_limits<S>::infinity(), 0, kNoLeaf, 0, 0};
  if (start != kNoLeaf) take_leaf(p, start, found);
  // Nodes still to search with their boxes' distance2, pruned on popping against the best found by then; a node's
  // children nearer than the best are pushed farthest first, so the nearest is searched next. The collapsed median
  // tree is at most 32 levels deep, with kNodeWidth - 1 waiting per level, and a node's children are each written
  // before the count decides whether they stay.
  struct Pending {
    std::uint32_t node;
    S box2;
  };
  Pending stack[32 * (kNodeWidth - 1) + kNodeWidth];
  int top = 0;
  std::uint32_t at = 0;
  for (;;) {
    if (at & kLeafBit) {
      if ((at & ~kLeafBit) != start) take_leaf(p, at & ~kLeafBit, found);
    } else {
      const BvhNode<S>& n = a.nodes[at];
      S box2[kNodeWidth];
      detail::bounds_distance2(p, n, box2);
      std::uint32_t order[kNodeWidth];
      detail::nearest_first<kNodeWidth>(box2, order);
      for (int j = kNodeWidth - 1; j >= 0; --j) {
        stack[top] = {n.child[order[j]], box2[order[j]]};
        top += box2[order[j]] <= found.best2;  // a tie may hold a triangle earlier in BVH order
      }
      // The two searched next, fetched whole now: a node or leaf is 11 or 12 cache lines, rarely all in the
      // first-level cache, whose loads otherwise wait until the search reaches it (with the folded least: 0.93 ->
      // 1.05 M queries/s at random points about the 86k-triangle torus, in-process A/B medians).
      for (int k = 1; k <= 2 && k <= top; ++k) prefetch<S>(stack[top - k].node);
    }
    while (top > 0 && !(stack[top - 1].box2 <= found.best2)) --top;
    if (top == 0) break;
    at = stack[--top].node;
  }
  return found;
}

template <class S>
void MeshDistance::prefetch(std::uint32_t id) const {
  const bool leaf = (id & kLeafBit) != 0;
  const char* at = leaf ? reinterpret_cast<const char*>(&arrays<S>().leaves[id & ~kLeafBit])
                        : reinterpret_cast<const char*>(&arrays<S>().nodes[id]);
  const std::size_t size = leaf ? sizeof(Leaf<S>) : sizeof(BvhNode<S>);
  for (std::size_t offset = 0; offset < size; offset += 64) __builtin_prefetch(at + offset);
}

template <class S>
MeshDistance::Closest<S> MeshDistance::closest_of(glm::vec<3, S> p, const Found<S>& found) const {
  const Arrays<S>& a = arrays<S>();
  Closest<S> best;
  // The corners from the leaf the search ended in, in cache (a.corners[found.slot] has the same values).
  std::array<glm::vec<3, S>, 3> corners = a.corners[0];
  if (found.leaf != kNoLeaf) {
    const Leaf<S>& l = a.leaves[found.leaf];
    for (int i = 0; i < 3; ++i) {
      corners[0][i] = l.a[i][found.lane];
      corners[1][i] = l.b[i][found.lane];
      corners[2][i] = l.c[i][found.lane];
    }
  }
  best.point = meshes::closest_on_triangle(p, corners, best.feature);
  // Where no triangle was found (a point with a NaN coordinate, or so far that every distance overflows), the
  // distance to triangle 0's point: NaN or +inf, never a finite number.
  best.distance2 = found.leaf == kNoLeaf ? glm::dot(p - best.point, p - best.point) : found.best2;
  best.triangle = order_[found.slot];
  best.pseudonormal = a.normals[found.slot][best.feature];
  best.face_normal = a.normals[found.slot][meshes::face];
  return best;
}

template <class S>
std::uint32_t MeshDistance::start_leaf(glm::vec<3, S> p) const {
  if (start_cells_ == 0) return kNoLeaf;
  const glm::vec3 cell = (glm::vec3(p) - start_origin_) * start_cells_per_unit_;
  const float last = static_cast<float>(start_cells_ - 1);
  int index[3];
  for (int i = 0; i < 3; ++i) {
    if (std::isnan(cell[i])) return kNoLeaf;
    index[i] = static_cast<int>(std::clamp(cell[i], 0.0f, last));
  }
  return start_leaves_[(static_cast<std::size_t>(index[2]) * start_cells_ + index[1]) * start_cells_ + index[0]];
}

template <class S>
MeshDistance::Closest<S> MeshDistance::closest(glm::vec<3, S> p) const {
  return closest_of(p, search(p, start_leaf(p)));
}

template <class S>
void MeshDistance::closest(const glm::vec<3, S>* points, Closest<S>* out, int n) const {
  Found<S> previous{0, 0, kNoLeaf, 0, 0};
  for (int i = 0; i < n; ++i) {
    const glm::vec<3, S> p = points[i], step = i > 0 ? p - points[i - 1] : glm::vec<3, S>(0);
    // Within the previous point's distance, that point's closest triangle lies within twice that distance of p: a
    // bound worth starting from. NaN compares false: from the root.
    const bool near = previous.leaf != kNoLeaf && glm::dot(step, step) <= previous.best2;
    previous = search(p, near ? previous.leaf : start_leaf(p));
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
