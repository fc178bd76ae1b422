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
#include <vector>

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

// A reference's normal at its hit p: the field's gradient there (double, forward mode), normalised; where it
// vanishes, against the ray's direction d.
glm::dvec3 field_normal(const sdf::Tape& tape, glm::dvec3 p, glm::dvec3 d);

// Requires sdf::interval_supported(tape). direction: unit length.
CertifiedHit certified_first_hit(const sdf::Tape& tape, glm::dvec3 origin, glm::dvec3 direction, double t_max);

// A Lipschitz constant proven along rays: the interval of the gradient's length (sdf::DualInterval::n) over
// boxes that cover each ray's path from its origin to its end, each piece halved while its bound exceeds the
// target and it is longer than kCertifiedLipschitzPiece (1 + t), within a budget of box evaluations. The bound
// over a box holds |grad f| at every point of it where f is differentiable: it is f's Lipschitz constant along
// the path where f is continuous (every operator's field is; a repetition's where its child is symmetric across
// the cell faces). What a marcher stepping f / L along those rays needs, and no more: the field far from them
// may be steeper.
struct CertifiedLipschitz {
  double upper = 0;  // max over the final pieces of their bound: a proven Lipschitz constant along the paths
  glm::dvec3 steepest{0};  // the centre of the piece with the largest bound
  double steepest_length = 0;  // and its length along its ray
  // A proven lower bound: the largest |f(a) - f(b)| / |a - b| over pairs at the unproven pieces (intervals at
  // both points); lower > declared proves the declared constant understated.
  double lower = 0;
  glm::dvec3 lower_at{0};
  int boxes = 0;     // evaluated
  int unproven = 0;  // final pieces whose bound stays above the target
};

struct RayPath {
  glm::dvec3 origin, direction;  // direction: unit length
  double t_end;
};

inline constexpr double kCertifiedLipschitzPiece = 1e-4;
// A bound within this factor of the declared constant proves it: the tolerance of sdf.lipschitz_over_declared,
// so that a declared constant equal to the true supremum (the rules' own) is provable.
inline constexpr double kLipschitzTolerance = 1.001;

// Requires sdf::interval_supported(tape). target: the constant to prove (the declared one, with its tolerance).
CertifiedLipschitz certify_lipschitz(const sdf::Tape& tape, const std::vector<RayPath>& paths, double target,
                                     int budget = 100000);

}  // namespace marchcheck::validation
