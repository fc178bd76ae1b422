// The only door to OpenMesh: its readers and writers, driven through our own importer and exporter so that a
// file's vertices and polygons arrive exactly as written (no merging, dropping or splitting of non-manifold faces).
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace marchcheck::meshes::detail {

enum class Format { obj, off, ply, stl };

// Polygons as read: face f uses indices[offsets[f] .. offsets[f + 1]); indices may be invalid (negative or past
// the vertex count) when the file is.
struct Polygons {
  std::vector<glm::dvec3> vertices;
  std::vector<int> indices;
  std::vector<std::size_t> offsets{0};
};

// False with a reason (possibly empty) when OpenMesh rejects the file or throws.
bool openmesh_read(const std::string& path, Polygons& out, std::string& reason);

// Writes the whole file to out; false with a reason when the writer fails or throws.
bool openmesh_write(const Mesh& mesh, Format format, std::ostream& out, std::string& reason);

}  // namespace marchcheck::meshes::detail
