#include "marchcheck/meshes/weld.hpp"

#include "vertex_grid.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <vector>

namespace marchcheck::meshes {

namespace detail {

VertexGrid::VertexGrid(const std::vector<glm::dvec3>& positions, double tolerance)
    : positions_(positions), tolerance_(tolerance) {
  if (!(tolerance >= 0) || !std::isfinite(tolerance))
    throw MeshError("weld: the tolerance must be a finite number >= 0");
  if (!positions.empty()) origin_ = positions[0];
  for (const glm::dvec3& p : positions) origin_ = glm::min(origin_, p);
}

// Cells twice the tolerance wide, counted from the positions' lowest corner (a mesh far from the origin keeps
// small cell numbers; p - origin is exact for nearby values): partners lie less than half a cell apart, so in the
// same cell or one of the 26 around it even after the division rounds (cell numbers are kept below 2^48, where
// it rounds by under 1/16). With tolerance 0 every position is its own cell (its bits): only equal positions meet.
VertexGrid::Cell VertexGrid::cell_of(glm::dvec3 p) const {
  Cell c{};
  for (int i = 0; i < 3; ++i) {
    const double x = tolerance_ > 0 ? std::floor((p[i] - origin_[i]) / (2 * tolerance_)) : p[i] == 0 ? 0.0 : p[i];
    if (tolerance_ > 0 && !(std::abs(x) <= 0x1p48)) {
      std::ostringstream what;
      what << "weld: a tolerance of " << tolerance_ << " is below double's resolution across coordinates from "
           << origin_[i] << " to " << p[i];
      throw MeshError(what.str());
    }
    c[static_cast<std::size_t>(i)] = tolerance_ > 0 ? static_cast<std::int64_t>(x) : std::bit_cast<std::int64_t>(x);
  }
  return c;
}

void VertexGrid::add(std::uint32_t vertex) { cells_[cell_of(positions_[vertex])].push_back(vertex); }

}  // namespace detail

WeldResult weld(Mesh& mesh, double tolerance) {
  detail::VertexGrid kept(mesh.vertices, tolerance);
  std::vector<std::uint32_t> into(mesh.vertices.size());
  WeldResult result;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    std::optional<std::uint32_t> partner;
    kept.find(mesh.vertices[v], [&](std::uint32_t k) {
      partner = k;
      return true;
    });
    if (partner) {
      into[v] = *partner;
      ++result.merged_vertices;
    } else {
      into[v] = v;
      kept.add(v);
    }
  }
  // Faces through the merge; then the vertices still used, renumbered in their order. Each keeps its number in
  // the file (a merged vertex goes by the one it became).
  std::vector<std::array<std::uint32_t, 3>> faces;
  std::vector<std::uint32_t> face_numbers;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    auto t = mesh.triangles[f];
    for (auto& i : t) i = into[i];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++result.removed_faces;
      continue;
    }
    faces.push_back(t);
    if (!mesh.face_numbers.empty()) face_numbers.push_back(mesh.face_numbers[f]);
  }
  constexpr std::uint32_t kUnused = ~0u;
  std::vector<std::uint32_t> number(mesh.vertices.size(), kUnused), vertex_numbers;
  std::vector<glm::dvec3> vertices;
  for (auto& t : faces)
    for (auto& i : t) {
      if (number[i] == kUnused) {
        number[i] = static_cast<std::uint32_t>(vertices.size());
        vertices.push_back(mesh.vertices[i]);
        if (!mesh.vertex_numbers.empty()) vertex_numbers.push_back(mesh.vertex_numbers[i]);
      }
      i = number[i];
    }
  mesh.vertices = std::move(vertices);
  mesh.triangles = std::move(faces);
  mesh.vertex_numbers = std::move(vertex_numbers);
  mesh.face_numbers = std::move(face_numbers);
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
