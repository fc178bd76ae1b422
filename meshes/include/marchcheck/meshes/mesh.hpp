// Triangle meshes as plain arrays: what the loaders produce, the generators build and the references consume.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace marchcheck::meshes {

// Triangles index into vertices; counter-clockwise seen from outside is the outward side.
struct Mesh {
  std::vector<glm::dvec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  // How the file this mesh was read from numbers what messages name, so that a user can find it there: vertex i is
  // the file's vertex vertex_numbers[i], triangle t part of its face face_numbers[t] (a polygon's fan shares one).
  // OBJ numbers both from 1, OFF and PLY from 0, STL its facets from 1 and its corners not at all (vertex_numbers
  // stays empty: positions name them). Empty for a mesh no file numbers: triangles are then counted from 1.
  std::vector<std::uint32_t> vertex_numbers = {};
  std::vector<std::uint32_t> face_numbers = {};
};

// Bad input: an unreadable or malformed file ("PATH: problem"), invalid generator parameters, or a mesh that
// cannot be written.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace marchcheck::meshes
