#include "marchcheck/meshes/weld.hpp"

#include <glm/geometric.hpp>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

namespace marchcheck::meshes {

WeldResult weld(Mesh& mesh, double tolerance) {
  if (!(tolerance >= 0) || !std::isfinite(tolerance))
    throw MeshError("weld: the tolerance must be a finite number >= 0");
  // Cells twice the tolerance wide: partners lie less than half a cell apart, so in the same cell or one of the 26
  // around it even after the division rounds (cell numbers are kept below 2^48, where it rounds by under 1/16).
  // With tolerance 0 every position is its own cell (its bits), so only equal positions merge.
  using Cell = std::array<std::int64_t, 3>;
  const auto cell_of = [&](glm::dvec3 p) {
    Cell c{};
    for (int i = 0; i < 3; ++i) {
      const double x = tolerance > 0 ? std::floor(p[i] / (2 * tolerance)) : p[i] == 0 ? 0.0 : p[i];
      if (tolerance > 0 && std::abs(x) > 0x1p48) {
        std::ostringstream what;
        what << "weld: a tolerance of " << tolerance << " is below double's resolution at a coordinate of " << p[i];
        throw MeshError(what.str());
      }
      c[static_cast<std::size_t>(i)] = tolerance > 0 ? static_cast<std::int64_t>(x) : std::bit_cast<std::int64_t>(x);
    }
    return c;
  };
  std::map<Cell, std::vector<std::uint32_t>> kept;
  std::vector<std::uint32_t> into(mesh.vertices.size());
  WeldResult result;
  // The first kept vertex within tolerance of p (cell c), if any.
  const auto partner = [&](glm::dvec3 p, const Cell& c) -> std::optional<std::uint32_t> {
    const int reach = tolerance > 0 ? 1 : 0;
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz) {
          const auto found = kept.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (found == kept.end()) continue;
          for (const std::uint32_t k : found->second)
            if (glm::distance(mesh.vertices[k], p) <= tolerance) return k;
        }
    return std::nullopt;
  };
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    const Cell c = cell_of(mesh.vertices[v]);
    if (const auto k = partner(mesh.vertices[v], c)) {
      into[v] = *k;
      ++result.merged_vertices;
    } else {
      into[v] = v;
      kept[c].push_back(v);
    }
  }
  // Faces through the merge; then the vertices still used, renumbered in their order.
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (auto t : mesh.triangles) {
    for (auto& i : t) i = into[i];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++result.removed_faces;
      continue;
    }
    faces.push_back(t);
  }
  constexpr std::uint32_t kUnused = ~0u;
  std::vector<std::uint32_t> number(mesh.vertices.size(), kUnused);
  std::vector<glm::dvec3> vertices;
  for (auto& t : faces)
    for (auto& i : t) {
      if (number[i] == kUnused) {
        number[i] = static_cast<std::uint32_t>(vertices.size());
        vertices.push_back(mesh.vertices[i]);
      }
      i = number[i];
    }
  mesh.vertices = std::move(vertices);
  mesh.triangles = std::move(faces);
  return result;
}

std::string describe(const WeldResult& r, double tolerance) {
  std::ostringstream out;
  out << "welded at " << tolerance << ": ";
  if (r.merged_vertices == 0 && r.removed_faces == 0) {
    out << "nothing to weld";
  } else {
    out << r.merged_vertices << " vertices merged, " << r.removed_faces << " faces with a repeated index removed";
  }
  return out.str();
}

}  // namespace marchcheck::meshes
