#include "marchcheck/validation/certified.hpp"

#include "marchcheck/sdf/interval.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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

glm::dvec3 field_normal(const sdf::Tape& tape, glm::dvec3 p, glm::dvec3 d) {
  const glm::dvec3 g = sdf::evaluate(tape, sdf::seeded(p)).d;
  return glm::length(g) > 0 ? glm::normalize(g) : -d;
}

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
        out.normal = field_normal(tape, o + d * out.t, d);
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

namespace {

// A proven slope of f along the piece [a, b] of a ray: the difference quotient along the gradient at its
// middle, over a step of a tenth of the piece, with the values' intervals (the distance rounded up).
double proven_slope(const sdf::Tape& tape, glm::dvec3 c, double length, glm::dvec3& at) {
  const glm::dvec3 g = sdf::evaluate(tape, sdf::seeded(c)).d;
  if (!(glm::length(g) > 0)) return 0;
  const glm::dvec3 e = c + glm::normalize(g) * (0.1 * length);
  auto point = [](glm::dvec3 p) { return glm::vec<3, Interval>(Interval(p.x), Interval(p.y), Interval(p.z)); };
  const Interval rise = abs(sdf::evaluate(tape, point(e)) - sdf::evaluate(tape, point(c)));
  const double run = std::nextafter(glm::length(e - c), std::numeric_limits<double>::infinity());
  at = c;
  return rise.lo / run;
}

}  // namespace

CertifiedLipschitz certify_lipschitz(const sdf::Tape& tape, const std::vector<RayPath>& paths, double target,
                                     int budget) {
  CertifiedLipschitz out;
  // Each ray's share of the budget, so that one rough path cannot starve the others.
  const int per_path = paths.empty() ? 0 : std::max(1, budget / static_cast<int>(paths.size()));
  for (const RayPath& path : paths) {
    std::vector<std::pair<double, double>> work{{0, path.t_end}};
    int spent = 0;
    while (!work.empty()) {
      const auto [a, b] = work.back();
      work.pop_back();
      const double bound = sdf::evaluate(tape, sdf::seeded(segment(path.origin, path.direction, a, b))).n;
      ++spent;
      const bool split = bound > target && b - a > kCertifiedLipschitzPiece * (1 + b) &&
                         spent + static_cast<int>(work.size()) + 2 <= per_path;
      if (split) {
        const double m = 0.5 * (a + b);
        work.push_back({m, b});
        work.push_back({a, m});
        continue;
      }
      const glm::dvec3 middle = path.origin + path.direction * (0.5 * (a + b));
      if (bound > out.upper) {
        out.upper = bound;
        out.steepest = middle;
        out.steepest_length = b - a;
      }
      if (bound > target) {
        ++out.unproven;
        glm::dvec3 at;
        const double slope = proven_slope(tape, middle, b - a, at);
        if (slope > out.lower) {
          out.lower = slope;
          out.lower_at = at;
        }
      }
    }
    out.boxes += spent;
  }
  return out;
}

}  // namespace marchcheck::validation
