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
};

// Bad input: an unreadable or malformed file ("PATH: problem"), invalid generator parameters, or a mesh that
// cannot be written.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace marchcheck::meshes
