// Independent zero-set references for tests: a shape's surface located from a closed-form inside/outside
// test alone (never from the SDF under test), and distances measured to those surface points.
#pragma once

#include "marchcheck/sdf/tape.hpp"
#include "marchcheck/sdf/lipschitz.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace marchcheck::testing {

using Inside = std::function<bool(glm::dvec3)>;

// Surface points where the inside test changes along the edges of a grid of spacing h over [lo, hi], each
// located by bisection to 1e-9 h. Any surface point with features larger than h lies within
// sampling_error(h) of one of them.
struct ZeroSet {
  std::vector<glm::dvec3> points;
  double h;

  static double sampling_error(double h) { return h * std::sqrt(3.0); }


  ZeroSet(const Inside& inside, glm::dvec3 lo, glm::dvec3 hi, double h_) : h(h_) {
    const glm::ivec3 n = glm::ivec3(glm::ceil((hi - lo) / h)) + 1;
    auto node = [&](int i, int j, int k) { return lo + glm::dvec3(i, j, k) * h; };
    for (int i = 0; i < n.x; ++i)
      for (int j = 0; j < n.y; ++j)
        for (int k = 0; k < n.z; ++k) {
          const glm::dvec3 a = node(i, j, k);
          const bool ia = inside(a);
          for (const glm::ivec3 d : {glm::ivec3(1, 0, 0), glm::ivec3(0, 1, 0), glm::ivec3(0, 0, 1)}) {
            glm::dvec3 b = node(i + d.x, j + d.y, k + d.z);
            if (inside(b) == ia) continue;
            glm::dvec3 x = a;
            for (int it = 0; it < 40; ++it) {
              const glm::dvec3 m = (x + b) * 0.5;
              (inside(m) == ia ? x : b) = m;
            }
            points.push_back((x + b) * 0.5);
          }
        }
  }

  // Distance from p to the nearest surface point (brute force: a few hundred queries over ~1e5 points is
  // faster than any index would be to build).
  double distance(glm::dvec3 p) const {
    double best2 = INFINITY;
    for (const auto& q : points) {
      const glm::dvec3 d = q - p;
      best2 = std::min(best2, d.x * d.x + d.y * d.y + d.z * d.z);
    }
    return std::sqrt(best2);
  }
};

// How a field compares with the true distance at query points.
struct KindMeasurement {
  double max_over = -INFINITY;   // max(|f| - d_ref): > 0 means f overestimates (not a bound)
  double max_under = -INFINITY;  // max(d_ref - |f|): how far from exact
  int sign_errors = 0;           // f < 0 disagrees with the inside test
  int queries = 0;
};

inline KindMeasurement measure_kind(const sdf::Tape& tape, const ZeroSet& zs, const Inside& inside, glm::dvec3 lo,
                                    glm::dvec3 hi, int count, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  KindMeasurement m;
  for (int i = 0; i < count; ++i) {
    const glm::dvec3 p = lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng));
    const double f = sdf::evaluate(tape, p), d = zs.distance(p);
    m.max_over = std::max(m.max_over, std::abs(f) - d);
    m.max_under = std::max(m.max_under, d - std::abs(f));
    // Points within the sampling error of the surface may sit on either side of it.
    if ((f < 0) != inside(p) && d > zs.h) ++m.sign_errors;
    ++m.queries;
  }
  return m;
}

// Largest |f(a) - f(b)| / |a - b| over random nearby pairs in [lo, hi] (finite differences, no derivatives).
inline double measure_lipschitz(const std::function<double(glm::dvec3)>& f, glm::dvec3 lo, glm::dvec3 hi, int pairs,
                                double step = 1e-4, unsigned seed = 11) {
  return sdf::measured_slope(f, lo, hi, pairs, step, seed);
}

}  // namespace marchcheck::testing
