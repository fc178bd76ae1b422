#include "marchcheck/validation/certified.hpp"

#include "marchcheck/sdf/interval.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace marchcheck::validation {

namespace {

using sdf::Interval;

// Every real point o + t d for t in [a, b], as a box.
glm::vec<3, Interval> segment(glm::dvec3 o, glm::dvec3 d, double a, double b) {
  const Interval t(a, b);
  return {Interval(o.x) + t * Interval(d.x), Interval(o.y) + t * Interval(d.y), Interval(o.z) + t * Interval(d.z)};
}

double width(double t) { return kCertifiedWidth * (1 + t); }

// The crossing in [a, b] (the field positive at a, negative at b) bisected while the midpoint's sign is provable.
double bisect(const sdf::Tape& tape, glm::dvec3 o, glm::dvec3 d, double a, double b, std::uint64_t& evaluations) {
  for (int i = 0; i < 60 && b - a > 1e-15 * (1 + b); ++i) {
    const double m = 0.5 * (a + b);
    const Interval f = sdf::evaluate(tape, segment(o, d, m, m));
    ++evaluations;
    if (f.lo > 0) {
      a = m;
    } else if (f.hi < 0) {
      b = m;
    } else {
      break;
    }
  }
  return 0.5 * (a + b);
}

}  // namespace

CertifiedHit certified_first_hit(const sdf::Tape& tape, glm::dvec3 o, glm::dvec3 d, double t_max) {
  CertifiedHit out;
  const Interval at_origin = sdf::evaluate(tape, segment(o, d, 0, 0));
  out.evaluations = 1;
  if (at_origin.hi < 0) {
    out.verdict = CertifiedHit::Verdict::inside;
    return out;
  }
  if (!(at_origin.lo > 0)) return out;  // on the surface within rounding: undecidable at t = 0
  // Segments still to examine, the nearest on top. Everything before the top one is proven positive.
  std::vector<std::pair<double, double>> stack{{0, t_max}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    if (out.evaluations >= kCertifiedBudget) {
      out.t_lo = a;
      out.t_hi = b;
      return out;
    }
    const Interval f = sdf::evaluate(tape, segment(o, d, a, b));
    ++out.evaluations;
    if (f.lo > 0) continue;  // no surface on this segment
    if (b - a <= width(a)) {
      const Interval at_b = sdf::evaluate(tape, segment(o, d, b, b));
      ++out.evaluations;
      if (at_b.hi < 0) {  // positive at a, negative at b: the first surface point lies in [a, b]
        out.verdict = CertifiedHit::Verdict::hit;
        out.t_lo = a;
        out.t_hi = b;
        out.t = bisect(tape, o, d, a, b, out.evaluations);
        const glm::dvec3 p = o + d * out.t;
        using D = sdf::Dual<double>;
        const glm::dvec3 g = sdf::evaluate(tape, glm::vec<3, D>(D(p.x, {1, 0, 0}), D(p.y, {0, 1, 0}), D(p.z, {0, 0, 1}))).d;
        out.normal = glm::length(g) > 0 ? glm::normalize(g) : -d;
        return out;
      }
      // Not yet proven either way: a thousand times finer, then undecidable.
      if (b - a <= 1e-3 * width(a)) {
        out.t_lo = a;
        out.t_hi = b;
        return out;
      }
    }
    const double m = 0.5 * (a + b);
    stack.push_back({m, b});
    stack.push_back({a, m});
  }
  out.verdict = CertifiedHit::Verdict::miss;
  return out;
}

}  // namespace marchcheck::validation
