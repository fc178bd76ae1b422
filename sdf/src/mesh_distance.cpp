#include "marchcheck/sdf/mesh_distance.hpp"

#include "marchcheck/meshes/checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>

namespace marchcheck::sdf {

namespace {

using glm::dvec3;

// Angle at corner a of triangle abc.
double corner_angle(dvec3 a, dvec3 b, dvec3 c) {
  const dvec3 u = glm::normalize(b - a), v = glm::normalize(c - a);
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

// The mesh must be a closed, consistently oriented solid with its normals outward: then every point has a
// sign. Its report, or MeshShapeError naming the problem.
meshes::MeshReport solid_report(const meshes::Mesh& mesh) {
  meshes::MeshReport report;
  try {
    report = meshes::inspect(mesh);
  } catch (const meshes::MeshError& e) {  // an index past the vertices
    throw MeshShapeError(e.what());
  }
  if (const std::string problem = meshes::solid_problem(report, mesh); !problem.empty()) throw MeshShapeError(problem);
  if (!report.outward) throw MeshShapeError("the mesh encloses a negative volume: it is inside out");
  return report;
}

// Face normals, angle-weighted vertex pseudonormals, and each directed edge's face: a solid has every edge once
// in each direction, so an edge's twin is the face across it.
struct Pseudonormals {
  std::vector<dvec3> face, vertex;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> directed;

  explicit Pseudonormals(const meshes::Mesh& mesh)
      : face(mesh.triangles.size()), vertex(mesh.vertices.size(), dvec3(0)) {
    const auto& vs = mesh.vertices;
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
      const auto& t = mesh.triangles[f];
      const dvec3 a = vs[t[0]], b = vs[t[1]], c = vs[t[2]];
      face[f] = glm::normalize(glm::cross(b - a, c - a));
      for (int i = 0; i < 3; ++i) {
        directed.emplace(std::pair{t[i], t[(i + 1) % 3]}, f);
        vertex[t[i]] += corner_angle(vs[t[i]], vs[t[(i + 1) % 3]], vs[t[(i + 2) % 3]]) * face[f];
      }
    }
  }
  // An edge's pseudonormal (edge i of face f runs from corner i to i + 1): the sum of its two faces' normals,
  // each weighted by the angle pi.
  dvec3 edge(const meshes::Mesh& mesh, std::uint32_t f, int i) const {
    const auto& t = mesh.triangles[f];
    return face[f] + face[directed.at({t[(i + 1) % 3], t[i]})];
  }
};

// An oriented box's axes for triangles [begin, end): the third their area-weighted mean normal, the others any
// two across it (which two changes the leaves a search reads by about 1%, measured at random points about a torus
// and an icosphere). Where the normals cancel (a closed piece), the coordinate axes: any frame bounds, the tight
// one just prunes more.
std::array<dvec3, 3> mean_plane_frame(const std::vector<std::array<dvec3, 3>>& corners, std::uint32_t begin,
                                      std::uint32_t end) {
  dvec3 normal(0);
  double area = 0;
  for (std::uint32_t i = begin; i < end; ++i) {
    const auto& t = corners[i];
    const dvec3 twice_area = glm::cross(t[1] - t[0], t[2] - t[0]);
    normal += twice_area;
    area += glm::length(twice_area);
  }
  if (!(glm::length(normal) > 1e-3 * area)) return {dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1)};
  const dvec3 n = glm::normalize(normal);
  const dvec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.6 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  return {u, glm::cross(n, u), n};
}

}  // namespace

// Child k's oriented box in node: the frame's axes and the box's centre rounded to S, and half extents that hold
// every corner of triangles [begin, end) along those rounded axes, computed in double, padded by 8 epsilons of the
// corner's L1 norm about the centre (four times that arithmetic's rounding) and rounded up to S.
template <class S>
void MeshDistance::set_oriented_box(BvhNode<S>& node, int k, const std::array<dvec3, 3>& frame,
                                    const std::vector<std::array<dvec3, 3>>& corners, std::uint32_t begin,
                                    std::uint32_t end) {
  dvec3 lo(INFINITY), hi(-INFINITY);
  for (std::uint32_t i = begin; i < end; ++i)
    for (const dvec3& x : corners[i])
      for (int r = 0; r < 3; ++r) {
        lo[r] = std::min(lo[r], glm::dot(x, frame[r]));
        hi[r] = std::max(hi[r], glm::dot(x, frame[r]));
      }
  const dvec3 mid = (lo + hi) / 2.0;
  const dvec3 centre = frame[0] * mid[0] + frame[1] * mid[1] + frame[2] * mid[2];
  glm::vec<3, S> axes[3];
  for (int r = 0; r < 3; ++r) axes[r] = glm::vec<3, S>(frame[r]);
  const glm::vec<3, S> c(centre);
  dvec3 half(0);
  for (std::uint32_t i = begin; i < end; ++i)
    for (const dvec3& x : corners[i]) {
      const dvec3 w = x - dvec3(c);
      const double l1 = std::abs(w.x) + std::abs(w.y) + std::abs(w.z);
      const double pad = 8 * std::numeric_limits<double>::epsilon() * l1;
      for (int r = 0; r < 3; ++r) half[r] = std::max(half[r], std::abs(glm::dot(w, dvec3(axes[r]))) + pad);
    }
  for (int r = 0; r < 3; ++r) {
    node.centre[r][k] = c[r];
    for (int i = 0; i < 3; ++i) node.axes[r][i][k] = axes[r][i];
    S h = static_cast<S>(half[r]);
    if (h < half[r]) h = std::nextafter(h, S(INFINITY));
    node.half[r][k] = h;
  }
}

// A node of the binary tree the wide one is collapsed from.
struct MeshDistance::BinaryNode {
  dvec3 lo, hi;
  std::uint32_t first;   // leaf: first triangle (BVH order); inner: left child
  std::uint32_t second;  // inner: right child
  std::uint32_t count;   // leaf: how many triangles; inner: 0
  std::uint32_t begin, end;  // its triangles' BVH positions, leaf or inner
  double area() const {
    const dvec3 e = hi - lo;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

MeshDistance::MeshDistance(const meshes::Mesh& mesh, std::string note)
    : mesh_(mesh), report_(solid_report(mesh)), note_(std::move(note)) {
  const auto& vs = mesh.vertices;
  const auto& ts = mesh.triangles;
  const Pseudonormals normals(mesh);

  std::vector<dvec3> centroids(ts.size());
  bounds_ = Box3{dvec3(INFINITY), dvec3(-INFINITY)};
  for (std::uint32_t f = 0; f < ts.size(); ++f) {
    centroids[f] = (vs[ts[f][0]] + vs[ts[f][1]] + vs[ts[f][2]]) / 3.0;
    for (int i = 0; i < 3; ++i) {
      bounds_.lo = glm::min(bounds_.lo, vs[ts[f][i]]);
      bounds_.hi = glm::max(bounds_.hi, vs[ts[f][i]]);
    }
  }
  order_.resize(ts.size());
  std::iota(order_.begin(), order_.end(), 0u);
  std::vector<BinaryNode> binary;
  split(binary, centroids, 0, static_cast<std::uint32_t>(ts.size()));

  Arrays<double> d;
  for (const std::uint32_t f : order_) {
    const auto& t = ts[f];
    d.corners.push_back({vs[t[0]], vs[t[1]], vs[t[2]]});
    d.normals.push_back({normals.vertex[t[0]], normals.vertex[t[1]], normals.vertex[t[2]], normals.edge(mesh, f, 0),
                         normals.edge(mesh, f, 1), normals.edge(mesh, f, 2), normals.face[f]});
  }
  for (const auto& c : d.corners) single_.corners.push_back({glm::vec3(c[0]), glm::vec3(c[1]), glm::vec3(c[2])});
  for (const auto& n : d.normals) {
    std::array<glm::vec3, 7> f;
    for (size_t i = 0; i < 7; ++i) f[i] = glm::vec3(n[i]);
    single_.normals.push_back(f);
  }
  collapse(binary, 0, true, d);
  double_ = std::move(d);
  build_start_grid();
}

// About two cells per leaf across (the cube root of the leaves, doubled), at most 32 a side: 32^3 searches at most,
// tens of milliseconds against the construction's checks of the mesh.
void MeshDistance::build_start_grid() {
  const auto leaves = static_cast<double>(single_.leaves.size());
  const int cells = std::min(32, static_cast<int>(std::ceil(2 * std::cbrt(leaves))));
  if (cells < 2) return;
  const glm::dvec3 size = bounds_.size();
  start_origin_ = glm::vec3(bounds_.lo);
  start_cells_per_unit_ = glm::vec3(glm::dvec3(cells) / glm::max(size, glm::dvec3(1e-30)));
  start_leaves_.resize(static_cast<size_t>(cells) * cells * cells);
  for (int z = 0, i = 0; z < cells; ++z)
    for (int y = 0; y < cells; ++y)
      for (int x = 0; x < cells; ++x, ++i) {
        const glm::vec3 centre(bounds_.lo + (glm::dvec3(x, y, z) + 0.5) / double(cells) * size);
        start_leaves_[i] = search(centre, kNoLeaf).leaf;
      }
  start_cells_ = cells;
}

// Median split on the longest axis of the centroids' box, at a multiple of the leaf width so leaves are full.
std::uint32_t MeshDistance::split(std::vector<BinaryNode>& binary, const std::vector<dvec3>& centroids,
                                  std::uint32_t first, std::uint32_t count) {
  const auto& vs = mesh_.vertices;
  const auto& ts = mesh_.triangles;
  const auto index = static_cast<std::uint32_t>(binary.size());
  binary.push_back({dvec3(INFINITY), dvec3(-INFINITY), first, 0, count, first, first + count});
  dvec3 clo(INFINITY), chi(-INFINITY);
  for (std::uint32_t i = first; i < first + count; ++i) {
    for (int k = 0; k < 3; ++k) {
      binary[index].lo = glm::min(binary[index].lo, vs[ts[order_[i]][k]]);
      binary[index].hi = glm::max(binary[index].hi, vs[ts[order_[i]][k]]);
    }
    clo = glm::min(clo, centroids[order_[i]]);
    chi = glm::max(chi, centroids[order_[i]]);
  }
  if (count <= kLeafWidth) return index;
  const dvec3 extent = chi - clo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const std::uint32_t half = (count / 2 + kLeafWidth - 1) / kLeafWidth * kLeafWidth;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](std::uint32_t x, std::uint32_t y) { return centroids[x][axis] < centroids[y][axis]; });
  const std::uint32_t left = split(binary, centroids, first, half);
  const std::uint32_t right = split(binary, centroids, first + half, count - half);
  binary[index].first = left;
  binary[index].second = right;
  binary[index].count = 0;
  return index;
}

// Collapsed to kNodeWidth children per node: an inner child with the largest box is replaced by its two children
// until there are kNodeWidth. Float boxes are rounded outwards, so a float query never prunes a box that holds its
// closest triangle. The root is a full-width node even over a single leaf.
std::uint32_t MeshDistance::collapse(const std::vector<BinaryNode>& binary, std::uint32_t at, bool root,
                                     Arrays<double>& d) {
  const BinaryNode& b = binary[at];
  if (b.count > 0 && !root) {
    const auto leaf = static_cast<std::uint32_t>(d.leaves.size());
    add_leaf(d, b.first, b.count);
    add_leaf(single_, b.first, b.count);
    return leaf | kLeafBit;
  }
  std::vector<std::uint32_t> children = b.count > 0 ? std::vector{at} : std::vector{b.first, b.second};
  while (children.size() < kNodeWidth) {
    auto widest = children.end();
    for (auto c = children.begin(); c != children.end(); ++c)
      if (binary[*c].count == 0 && (widest == children.end() || binary[*c].area() > binary[*widest].area()))
        widest = c;
    if (widest == children.end()) break;
    const BinaryNode& w = binary[*widest];
    *widest = w.first;
    children.push_back(w.second);
  }
  const auto index = static_cast<std::uint32_t>(d.nodes.size());
  d.nodes.emplace_back();
  single_.nodes.emplace_back();
  for (int k = 0; k < kNodeWidth; ++k) {
    const bool used = k < static_cast<int>(children.size());
    if (used) {
      const BinaryNode& c = binary[children[k]];
      const std::array<dvec3, 3> frame = mean_plane_frame(d.corners, c.begin, c.end);
      set_oriented_box(d.nodes[index], k, frame, d.corners, c.begin, c.end);
      set_oriented_box(single_.nodes[index], k, frame, d.corners, c.begin, c.end);
    }
    for (int i = 0; i < 3; ++i) {
      const double lo = used ? binary[children[k]].lo[i] : NAN;
      const double hi = used ? binary[children[k]].hi[i] : NAN;
      d.nodes[index].lo[i][k] = lo;
      d.nodes[index].hi[i][k] = hi;
      float flo = static_cast<float>(lo), fhi = static_cast<float>(hi);
      if (flo > lo) flo = std::nextafter(flo, -INFINITY);
      if (fhi < hi) fhi = std::nextafter(fhi, INFINITY);
      single_.nodes[index].lo[i][k] = flo;
      single_.nodes[index].hi[i][k] = fhi;
    }
    const std::uint32_t child = used ? collapse(binary, children[k], false, d) : 0;
    d.nodes[index].child[k] = child;
    single_.nodes[index].child[k] = child;
  }
  return index;
}

template <class S>
void MeshDistance::add_leaf(Arrays<S>& arrays, std::uint32_t first, std::uint32_t count) {
  Leaf<S>& l = arrays.leaves.emplace_back();
  arrays.leaf_first.push_back(first);
  for (std::uint32_t k = 0; k < kLeafWidth; ++k) {
    const auto& t = arrays.corners[first + std::min(k, count - 1)];
    const glm::vec<3, S> n = meshes::face_normal<S>(t[1] - t[0], t[2] - t[0], t[2] - t[1]);  // in S, as the search's
    for (int i = 0; i < 3; ++i) {
      l.a[i][k] = t[0][i];
      l.b[i][k] = t[1][i];
      l.c[i][k] = t[2][i];
      l.n[i][k] = n[i];
    }
  }
}

}  // namespace marchcheck::sdf
