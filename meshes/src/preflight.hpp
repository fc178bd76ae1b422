// Our own scan of a mesh file before OpenMesh parses it. OpenMesh 9 is silent about several defects: its OBJ
// reader drops vertex lines it cannot parse (shifting every later index), its OFF and ASCII PLY readers read
// zeros after a "nan" and carry on, ASCII PLY clamps 1e50 to FLT_MAX, the STL readers turn NaN into a merged or
// zero vertex, a truncated OFF repeats its last face, huge header counts go straight into reserve(), and a PLY
// list count the file does not hold has it push indices until memory runs out. The scan names the line and the
// problem; what it does not look at (binary PLY values, binary STL normals) the checks after reading catch.
#pragma once

#include "openmesh_io.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace marchcheck::meshes::detail {

// What the file itself announces, to hold OpenMesh's result against.
struct Expected {
  std::optional<std::size_t> vertices;
  std::optional<std::size_t> faces;
};

// Throws MeshError("PATH: problem") on the first defect found.
Expected preflight(Format format, const std::string& path, std::string_view content);

}  // namespace marchcheck::meshes::detail
