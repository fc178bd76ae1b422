#include "marchcheck/meshes/checks.hpp"

#include "self_intersections.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <numeric>
#include <string>
#include <utility>

namespace marchcheck::meshes {
namespace {

using glm::dvec3;

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

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
  std::vector<std::size_t> parent(ends.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  const auto root = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::size_t components = ends.size();
  for (const auto& [a, b] : link) {
    const std::size_t i = local(a), j = local(b);
    if (++degree[i] > 2 || ++degree[j] > 2) return false;
    const std::size_t ri = root(i), rj = root(j);
    if (ri != rj) {
      parent[ri] = rj;
      --components;
    }
  }
  return components == 1;
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
  for (const auto& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++report.degenerate_faces;
      continue;
    }
    proper.push_back(t);
    const dvec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    const double longest2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    if (glm::length(glm::cross(b - a, c - a)) <= 1e-12 * longest2) ++report.degenerate_faces;
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
  bool consistent = true;
  for (std::size_t i = 0; i < directed.size();) {
    std::size_t j = i, forward = 0;
    for (; j < directed.size() && directed[j].first == directed[i].first; ++j) forward += directed[j].second;
    const std::size_t uses = j - i;
    if (uses == 1) ++report.boundary_edges;
    if (uses > 2) ++report.nonmanifold_edges;
    if (uses > 1 && 2 * forward != uses) consistent = false;
    i = j;
  }

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
    if (!single_fan(link)) ++report.nonmanifold_vertices;
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

std::string solid_problem(const MeshReport& r) {
  const auto count = [](int n, const char* what) { return std::to_string(n) + " " + what; };
  if (r.degenerate_faces > 0)
    return count(r.degenerate_faces, "degenerate faces (a repeated index, or zero area up to rounding)");
  if (!r.closed) return r.boundary_edges > 0 ? "open: " + count(r.boundary_edges, "boundary edges") : "no triangles";
  if (r.nonmanifold_edges > 0) return "non-manifold: " + count(r.nonmanifold_edges, "edges with three or more faces");
  if (r.nonmanifold_vertices > 0)
    return "non-manifold: " + count(r.nonmanifold_vertices, "pinched vertices (their faces form no single fan)");
  if (!r.consistently_oriented) return "inconsistently oriented: faces sharing an edge run along it the same way";
  if (!r.crossing_triangles.empty()) {
    // The first few pairs, counted from 1 as the faces come in the file (after polygons are split into triangles).
    std::string pairs;
    constexpr std::size_t kShown = 3;
    for (std::size_t i = 0; i < std::min(kShown, r.crossing_triangles.size()); ++i)
      pairs += (i ? ", " : "") + std::to_string(r.crossing_triangles[i][0] + 1) + " and " +
               std::to_string(r.crossing_triangles[i][1] + 1);
    return "self-intersecting: " + std::to_string(r.crossing_triangles.size()) + " pairs of triangles pass through "
           "each other (triangles " + pairs + (r.crossing_triangles.size() > kShown ? ", ..." : "") +
           "), so the mesh has no single inside and its distance no sign";
  }
  return "";
}

}  // namespace marchcheck::meshes
