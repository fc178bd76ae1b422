// The certified first hit along a ray: interval arithmetic (sdf/interval.hpp) over the segments of [0, t_max],
// depth first, discards each segment where the field is provably positive; the first one it cannot discard is
// cut down to kCertifiedWidth, and a crossing is proven there when the field is provably negative at its far
// end (everything before was proven positive: the intermediate value theorem). It trusts no Lipschitz constant:
// a feature thinner than any step the field's value allows is found all the same. Where neither can be proven
// (a grazing touch, a surface the field only reaches, f = 0 over a stretch), the ray is undecidable at this
// width: said, never guessed.
#pragma once

#include "marchcheck/sdf/tape.hpp"

#include <glm/glm.hpp>

#include <cstdint>

namespace marchcheck::validation {

struct CertifiedHit {
  enum class Verdict { hit, miss, inside, undecidable };
  Verdict verdict = Verdict::undecidable;
  // hit: the first point of the surface lies in [t_lo, t_hi], t the crossing bisected within it;
  // undecidable: the segment where the proof stopped.
  double t_lo = 0, t_hi = 0, t = 0;
  glm::dvec3 normal{0};  // hit: the field's gradient at t (double, forward mode), normalised
  std::uint64_t evaluations = 0;  // interval evaluations spent
};

// Segments are cut down to width(t) = kCertifiedWidth (1 + t) before a ray is called undecidable: a thousandth
// of the tightest hit threshold marchcheck's scenes use (1e-4 at unit distance), so no marcher's t error is
// judged against a certified bracket as wide as a tenth of its own tolerance.
inline constexpr double kCertifiedWidth = 1e-7;
// Interval evaluations one ray may spend before it is undecidable (a field whose intervals never tighten).
inline constexpr std::uint64_t kCertifiedBudget = 200000;

// Requires sdf::interval_supported(tape). direction: unit length.
CertifiedHit certified_first_hit(const sdf::Tape& tape, glm::dvec3 origin, glm::dvec3 direction, double t_max);

}  // namespace marchcheck::validation
