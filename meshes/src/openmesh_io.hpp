// The only door to OpenMesh: its readers and writers, driven through our own importer and exporter so that a
// file's vertices and polygons arrive exactly as written (no merging, dropping or splitting of non-manifold faces).
// In a module of its own, libmarchcheck_openmesh.so, loaded on the first mesh file read or written: linked to the
// meshes library, every command paid OpenMesh's loading and static constructors (2.5 ms of an empty program's
// start-up; with EGL and OpenGL's, about 1 ms of marchcheck's).
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

struct OpenMeshModule {
  // False with a reason (possibly empty) when OpenMesh rejects the file or throws.
  bool (*read)(const std::string& path, Polygons& out, std::string& reason);
  // Writes the whole file to out; false with a reason when the writer fails or throws.
  bool (*write)(const Mesh& mesh, Format format, std::ostream& out, std::string& reason);
};

// The module, loaded from beside libmarchcheck_meshes on first call (thread-safe). Throws std::runtime_error naming
// the file when it cannot be loaded.
const OpenMeshModule& openmesh();

}  // namespace marchcheck::meshes::detail

// The module's one entry point.
extern "C" const marchcheck::meshes::detail::OpenMeshModule* marchcheck_openmesh_module();
