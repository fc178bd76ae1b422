// Mesh files through OpenMesh: OBJ, OFF, PLY and STL (ASCII or binary), chosen by extension (any case).
//
// Precision: OpenMesh 9 reads and writes vertex positions as 32-bit floats in all four formats, so a save/load
// round trip rounds every coordinate to the nearest float (relative error <= 2^-24, about 6e-8) and distances to
// a reloaded mesh agree to about 1e-7 relative. Coordinates beyond the float range cannot be written.
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <string>

namespace marchcheck::meshes {

// Polygons are fan-triangulated. STL files get bit-identical vertex positions merged (STL stores no shared
// vertices). Throws MeshError "PATH: problem" for a missing or unreadable file, an unknown extension, malformed or
// truncated content, NaN/Inf or out-of-float-range coordinates, out-of-range indices, or no triangles at all.
Mesh load_mesh(const std::string& path);

// A mesh by source: "procedural:SPEC" (see procedural_mesh), else a file for load_mesh. Throws MeshError.
Mesh load_mesh_source(const std::string& source);

// Writes OBJ, OFF (ASCII), PLY or STL (binary) by extension, atomically: a temporary ".NAME.tmp-PID.EXT" in the
// same folder, then a rename. Throws MeshError naming the path if the mesh is invalid (no triangles, bad index,
// non-finite or out-of-float-range coordinate) or the file cannot be written; a failed save leaves no file behind.
void save_mesh(const Mesh& mesh, const std::string& path);

}  // namespace marchcheck::meshes
