// Vertices near a point, found through cells: what weld merges and what the mesh checks point out as a split seam.
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <glm/geometric.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <vector>

namespace marchcheck::meshes::detail {

class VertexGrid {
 public:
  // Throws MeshError for a negative or non-finite tolerance, or (on add) one below double's resolution across the
  // positions' extent. Tolerance 0 finds exactly equal positions only (-0 and +0 alike).
  VertexGrid(const std::vector<glm::dvec3>& positions, double tolerance);

  void add(std::uint32_t vertex);

  // Calls visit(k) for each added vertex k within tolerance of p, cell by cell in a fixed order and in the order
  // added within a cell, until visit returns true.
  template <class Visit>
  void find(glm::dvec3 p, Visit visit) const {
    const Cell c = cell_of(p);
    const int reach = tolerance_ > 0 ? 1 : 0;
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz) {
          const auto found = cells_.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (found == cells_.end()) continue;
          for (const std::uint32_t k : found->second)
            if (glm::distance(positions_[k], p) <= tolerance_ && visit(k)) return;
        }
  }

 private:
  using Cell = std::array<std::int64_t, 3>;
  Cell cell_of(glm::dvec3 p) const;

  const std::vector<glm::dvec3>& positions_;
  double tolerance_;
  glm::dvec3 origin_{0};  // the positions' lowest corner
  std::map<Cell, std::vector<std::uint32_t>> cells_;
};

}  // namespace marchcheck::meshes::detail
