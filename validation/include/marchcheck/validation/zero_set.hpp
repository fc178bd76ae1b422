// Zero-set references: a primitive's surface meshed procedurally with a known error bound (the Hausdorff distance
// between mesh and surface), and the field's |f| compared with the CGAL distance to that mesh. The field is seen
// only through its zero set's mesh, never called by the reference. For an exact field the two differ by at most
// the mesh's error everywhere.
#pragma once

#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <optional>

namespace marchcheck::validation {

// The procedural mesh of a sphere, torus or box node's surface; nullopt for any other node.
std::optional<meshes::ProceduralMesh> zero_set_mesh(const sdf::Node& primitive);

struct ZeroSetCheck {
  double exact_err_max = 0;  // sdf.exact_err_max: the largest | |f(p)| - distance to the mesh |
  double limit = 0;          // the mesh's error bound, plus double rounding at the mesh's scale
  int samples = 0;
  bool pass() const { return exact_err_max <= limit; }
};

// |f| (evaluated in double) against the distance to the mesh at points drawn uniformly from the mesh's bounds
// grown by half their size on each side (fixed seed).
ZeroSetCheck exact_against_zero_set(const sdf::Tape& field, const meshes::ProceduralMesh& zero_set, int samples = 2000,
                                    unsigned seed = 1);

}  // namespace marchcheck::validation
