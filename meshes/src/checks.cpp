#include "marchcheck/meshes/checks.hpp"

#include "self_intersections.hpp"
#include "vertex_grid.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <numeric>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>

namespace marchcheck::meshes {
namespace {

using glm::dvec3;

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

// Disjoint sets of indices, for connected components.
struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
  std::size_t root(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  bool join(std::size_t i, std::size_t j) {
    const std::size_t ri = root(i), rj = root(j);
    parent[ri] = rj;
    return ri != rj;
  }
};

// Whether the faces around one vertex, given as the opposite edge of each, form a single fan: the link is one
// path or one cycle (no link vertex of degree > 2, one connected component).
bool single_fan(std::vector<std::pair<std::uint32_t, std::uint32_t>>& link) {
  std::vector<std::uint32_t> ends;
  for (const auto& [a, b] : link) {
    ends.push_back(a);
    ends.push_back(b);
  }
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  const auto local = [&](std::uint32_t v) {
    return static_cast<std::size_t>(std::lower_bound(ends.begin(), ends.end(), v) - ends.begin());
  };
  std::vector<int> degree(ends.size(), 0);
  UnionFind sets(ends.size());
  std::size_t components = ends.size();
  for (const auto& [a, b] : link) {
    const std::size_t i = local(a), j = local(b);
    if (++degree[i] > 2 || ++degree[j] > 2) return false;
    components -= sets.join(i, j);
  }
  return components == 1;
}

// The smallest weld tolerance to suggest: 2^-45 of the mesh's extent (VertexGrid resolves down to 2^-49 of it).
double weld_resolution(const Mesh& mesh) {
  if (mesh.vertices.empty()) return 1e-300;
  dvec3 lo(mesh.vertices[0]), hi(lo);
  for (const dvec3& p : mesh.vertices) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const dvec3 extent = hi - lo;
  return std::max(0x1p-45 * std::max({extent.x, extent.y, extent.z}), 1e-300);
}

// Counts the boundary vertices (given with repeats) that have another boundary vertex within kSeamReach of the
// boundary's bounding diagonal, or within the weld resolution where that is wider.
void seams(const Mesh& mesh, std::vector<std::uint32_t> boundary, MeshReport& report) {
  std::sort(boundary.begin(), boundary.end());
  boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
  if (boundary.size() < 2) return;
  dvec3 lo(mesh.vertices[boundary[0]]), hi(lo);
  for (const std::uint32_t v : boundary) {
    lo = glm::min(lo, mesh.vertices[v]);
    hi = glm::max(hi, mesh.vertices[v]);
  }
  const double reach = std::max(kSeamReach * glm::distance(lo, hi), weld_resolution(mesh));
  if (!(reach > 0)) return;
  detail::VertexGrid grid(mesh.vertices, reach);
  for (const std::uint32_t v : boundary) grid.add(v);
  for (const std::uint32_t v : boundary) {
    double nearest = reach + 1;
    grid.find(mesh.vertices[v], [&](std::uint32_t k) {
      if (k != v) nearest = std::min(nearest, glm::distance(mesh.vertices[k], mesh.vertices[v]));
      return false;
    });
    if (nearest <= reach) {
      ++report.seam_vertices;
      report.seam_gap = std::max(report.seam_gap, nearest);
    }
  }
}

}  // namespace

MeshReport inspect(const Mesh& mesh) {
  const std::size_t n_vertices = mesh.vertices.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const std::uint32_t index : mesh.triangles[t])
      if (index >= n_vertices)
        throw MeshError("inspect: triangle " + std::to_string(t) + " refers to vertex " + std::to_string(index) +
                        ", but the mesh has " + std::to_string(n_vertices) + " vertices");
  MeshReport report;

  // Degenerate faces; those with a repeated index have no proper edges and are left out of the topology.
  std::vector<std::array<std::uint32_t, 3>> proper;
  proper.reserve(mesh.triangles.size());
  const auto degenerate = [&](std::size_t f) {
    if (report.degenerate_faces++ < static_cast<int>(kReportExamples)) report.degenerate_faces_at.push_back(f);
  };
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      degenerate(f);
      continue;
    }
    proper.push_back(t);
    const dvec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    const double longest2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    if (glm::length(glm::cross(b - a, c - a)) <= 1e-12 * longest2) degenerate(f);
  }

  // Edges: how many faces use each, and in which direction.
  std::vector<std::pair<std::uint64_t, bool>> directed;  // key, runs from the smaller index to the larger
  directed.reserve(proper.size() * 3);
  for (const auto& t : proper)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      directed.emplace_back(edge_key(a, b), a < b);
    }
  std::sort(directed.begin(), directed.end());
  const auto note = [&](int& count, std::vector<std::array<std::uint32_t, 2>>& at, std::uint64_t key) {
    if (count++ < static_cast<int>(kReportExamples))
      at.push_back({static_cast<std::uint32_t>(key >> 32), static_cast<std::uint32_t>(key & 0xffffffffu)});
  };
  UnionFind loops(n_vertices);
  std::vector<std::uint32_t> on_boundary;
  for (std::size_t i = 0; i < directed.size();) {
    std::size_t j = i, forward = 0;
    for (; j < directed.size() && directed[j].first == directed[i].first; ++j) forward += directed[j].second;
    const std::size_t uses = j - i;
    const std::uint64_t key = directed[i].first;
    if (uses == 1) {
      note(report.boundary_edges, report.boundary_edges_at, key);
      const auto a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key & 0xffffffffu);
      loops.join(a, b);
      on_boundary.push_back(a);
      on_boundary.push_back(b);
    }
    if (uses > 2) note(report.nonmanifold_edges, report.nonmanifold_edges_at, key);
    if (uses > 1 && 2 * forward != uses) note(report.misoriented_edges, report.misoriented_edges_at, key);
    i = j;
  }
  seams(mesh, on_boundary, report);
  for (std::uint32_t& v : on_boundary) v = static_cast<std::uint32_t>(loops.root(v));
  std::sort(on_boundary.begin(), on_boundary.end());
  report.boundary_loops = static_cast<int>(std::unique(on_boundary.begin(), on_boundary.end()) - on_boundary.begin());
  const bool consistent = report.misoriented_edges == 0;

  // Fans: for each vertex, the edges opposite it in its faces.
  std::vector<std::size_t> start(n_vertices + 1, 0);
  for (const auto& t : proper)
    for (const std::uint32_t v : t) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> opposite(start.back());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (const auto& t : proper) {
    opposite[fill[t[0]]++] = {t[1], t[2]};
    opposite[fill[t[1]]++] = {t[2], t[0]};
    opposite[fill[t[2]]++] = {t[0], t[1]};
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> link;
  for (std::size_t v = 0; v < n_vertices; ++v) {
    if (start[v] == start[v + 1]) continue;
    link.assign(opposite.begin() + static_cast<std::ptrdiff_t>(start[v]),
                opposite.begin() + static_cast<std::ptrdiff_t>(start[v + 1]));
    if (!single_fan(link) && report.nonmanifold_vertices++ < static_cast<int>(kReportExamples))
      report.pinched_vertices_at.push_back(static_cast<std::uint32_t>(v));
  }

  // Duplicates: equal positions (-0 and +0 alike) after the first.
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x == 0 ? 0.0 : x); };
  std::vector<std::array<std::uint64_t, 3>> keys;
  keys.reserve(n_vertices);
  for (const dvec3& p : mesh.vertices) keys.push_back({bits(p.x), bits(p.y), bits(p.z)});
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 1; i < keys.size(); ++i) report.duplicate_vertices += keys[i] == keys[i - 1];

  // Volume about the first vertex (smaller products than about the origin for meshes far from it).
  if (!mesh.vertices.empty()) {
    const dvec3 o = mesh.vertices.front();
    double six_volume = 0;
    for (const auto& t : mesh.triangles)
      six_volume += glm::dot(mesh.vertices[t[0]] - o,
                             glm::cross(mesh.vertices[t[1]] - o, mesh.vertices[t[2]] - o));
    report.signed_volume = six_volume / 6;
  }

  report.closed = !proper.empty() && report.boundary_edges == 0;
  report.manifold = report.nonmanifold_edges == 0 && report.nonmanifold_vertices == 0;
  report.consistently_oriented = consistent;
  report.outward = report.closed && consistent && report.signed_volume > 0;
  if (report.closed && report.manifold && consistent && report.degenerate_faces == 0)
    report.crossing_triangles = crossing_triangles(mesh);
  return report;
}

namespace {

std::string position(dvec3 p) {
  std::ostringstream out;
  out << std::setprecision(7) << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return out.str();
}

// "N what: A, B, C, ...": the count and where the first kReportExamples lie.
template <class T, class Show>
std::string counted(int n, const std::string& what, const std::vector<T>& at, Show show) {
  std::string out = std::to_string(n) + " " + what;
  const std::size_t shown = std::min(at.size(), kReportExamples);
  for (std::size_t i = 0; i < shown; ++i) out += (i ? ", " : ": ") + show(at[i]);
  return out + (static_cast<std::size_t>(n) > shown && shown > 0 ? ", ..." : "");
}

// Vertices and faces as the file the mesh came from names them (Mesh::vertex_numbers, face_numbers); vertices
// always with their position, which every format holds.
struct Names {
  const Mesh& mesh;
  std::string vertex(std::uint32_t v) const {
    const std::string at = position(mesh.vertices[v]);
    return mesh.vertex_numbers.empty() ? at : "vertex " + std::to_string(mesh.vertex_numbers[v]) + " at " + at;
  }
  std::string edge(const std::array<std::uint32_t, 2>& e) const {
    const std::string at = position(mesh.vertices[e[0]]) + "-" + position(mesh.vertices[e[1]]);
    if (mesh.vertex_numbers.empty()) return at;
    return "vertices " + std::to_string(mesh.vertex_numbers[e[0]]) + "-" + std::to_string(mesh.vertex_numbers[e[1]]) +
           " at " + at;
  }
  std::string face(std::size_t t) const {
    return std::to_string(mesh.face_numbers.empty() ? t + 1 : mesh.face_numbers[t]);
  }
};

// A weld value that merges vertices gap apart: the next power of ten at least twice gap, and not below what double
// resolves at the mesh's size (weld refuses less).
double weld_for(double gap, const Mesh& mesh) {
  return std::pow(10.0, std::ceil(std::log10(std::max(2 * gap, weld_resolution(mesh)))));
}

}  // namespace

std::string solid_problem(const MeshReport& r, const Mesh& mesh) {
  const Names name{mesh};
  const auto edge = [&](const std::array<std::uint32_t, 2>& e) { return name.edge(e); };
  std::vector<std::string> problems;
  if (r.degenerate_faces > 0)
    problems.push_back(counted(r.degenerate_faces, "degenerate faces (a repeated index, or zero area up to rounding)",
                               r.degenerate_faces_at, [&](std::size_t f) { return "face " + name.face(f); }));
  if (r.boundary_edges > 0)
    problems.push_back("open: " + counted(r.boundary_edges, "boundary edges in " + std::to_string(r.boundary_loops) +
                                          (r.boundary_loops == 1 ? " loop" : " loops"),
                                          r.boundary_edges_at, edge));
  if (r.nonmanifold_edges > 0)
    problems.push_back("non-manifold: " + counted(r.nonmanifold_edges, "edges with three or more faces",
                                                  r.nonmanifold_edges_at, edge));
  if (r.nonmanifold_vertices > 0)
    problems.push_back("non-manifold: " + counted(r.nonmanifold_vertices,
                                                  "pinched vertices (their faces form no single fan)",
                                                  r.pinched_vertices_at, [&](std::uint32_t v) { return name.vertex(v); }));
  if (r.misoriented_edges > 0)
    problems.push_back("inconsistently oriented: " + counted(r.misoriented_edges,
                                                             "edges whose faces run along them the same way",
                                                             r.misoriented_edges_at, edge));
  if (!r.crossing_triangles.empty())
    problems.push_back("self-intersecting: " +
                       counted(static_cast<int>(r.crossing_triangles.size()),
                               "pairs of triangles pass through each other, so the mesh has no single inside and its "
                               "distance no sign",
                               r.crossing_triangles, [&](const std::array<std::size_t, 2>& p) {
                                 return "faces " + name.face(p[0]) + " and " + name.face(p[1]);
                               }));
  if (problems.empty() && !r.closed) return "no triangles";
  if (r.seam_vertices > 0) {
    std::ostringstream seam;
    seam << std::setprecision(3) << r.seam_vertices << " boundary vertices lie ";
    if (r.seam_gap == 0) {
      seam << "at the position of";
    } else {
      seam << "within " << r.seam_gap << " of";
    }
    seam << " another boundary vertex: a seam split there (a mesh node's \"weld\": " << weld_for(r.seam_gap, mesh)
         << " merges them and may close it)";
    problems.push_back(seam.str());
  }
  std::string out;
  for (const auto& p : problems) out += (out.empty() ? "" : "; ") + p;
  return out;
}

}  // namespace marchcheck::meshes
