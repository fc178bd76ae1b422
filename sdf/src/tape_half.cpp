// The tape in binary16 (GLSL's mediump): its one instantiation, kept out of the float and double evaluators.
#include "marchcheck/sdf/half.hpp"
#include "marchcheck/sdf/tape.hpp"

namespace marchcheck::sdf::detail {

namespace {
vec3<Half> rounded(glm::vec3 p) { return {Half(p.x), Half(p.y), Half(p.z)}; }
}  // namespace

float evaluate_half(const Tape& tape, glm::vec3 p) { return run<Half, false>(tape, rounded(p)).distance; }

Sample<float> sample_half(const Tape& tape, glm::vec3 p) {
  const Sample<Half> s = run<Half, true>(tape, rounded(p));
  return {s.distance, s.material};
}

}  // namespace marchcheck::sdf::detail
