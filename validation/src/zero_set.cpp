#include "marchcheck/validation/zero_set.hpp"

#include "marchcheck/validation/mesh_reference.hpp"

#include <algorithm>
#include <cfloat>
#include <random>

namespace marchcheck::validation {

std::optional<meshes::ProceduralMesh> zero_set_mesh(const sdf::Node& n) {
  switch (n.op) {
    // Fine enough that the mesh error (about 3e-4 of the radius) is far below any hit threshold in use.
    case sdf::Op::sphere: return meshes::icosphere(n.scalar("radius"), 5);
    case sdf::Op::torus: return meshes::torus(n.scalar("major"), n.scalar("minor"), 128, 64);
    case sdf::Op::box: return meshes::box(n.vec3("half_size"));
    default: return std::nullopt;
  }
}

ZeroSetCheck exact_against_zero_set(const sdf::Tape& field, const meshes::ProceduralMesh& zero_set, int samples,
                                    unsigned seed) {
  const MeshReference ref(zero_set.mesh);
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& v : zero_set.mesh.vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const glm::dvec3 size = hi - lo;
  lo -= size * 0.5;
  ZeroSetCheck out;
  // Both distances are computed in double from coordinates of this size: a few hundred ulps.
  out.limit = zero_set.max_error + 256 * DBL_EPSILON * glm::length(size * 2.0);
  out.samples = samples;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < samples; ++i) {
    const glm::dvec3 p = lo + size * 2.0 * glm::dvec3(u(rng), u(rng), u(rng));
    out.exact_err_max =
        std::max(out.exact_err_max, std::abs(std::abs(sdf::evaluate(field, p)) - ref.unsigned_distance(p)));
  }
  return out;
}

}  // namespace marchcheck::validation
