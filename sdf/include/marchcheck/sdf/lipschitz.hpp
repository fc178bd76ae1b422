// The measured Lipschitz constant of a field: the largest slope over random nearby pairs (a lower bound on the
// true constant, which validation, the tests and the hard-case battery compare declarations and step sizes
// against). Beside derive_info's declared constant, for any callable field.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <random>

namespace marchcheck::sdf {

// The steepest pair found: |f(from + direction * step) - f(from)| / step.
struct SteepestPair {
  double slope = 0;
  glm::dvec3 from{0}, direction{0};
};

// The steepest of random nearby pairs in [lo, hi] (finite differences, fixed seed).
template <class Field>
SteepestPair steepest_pair(const Field& f, glm::dvec3 lo, glm::dvec3 hi, int pairs = 20000, double step = 1e-5,
                           unsigned seed = 2) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  SteepestPair worst;
  for (int i = 0; i < pairs; ++i) {
    const glm::dvec3 p = lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng));
    const glm::dvec3 d = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    const double slope = std::abs(f(p + d * step) - f(p)) / step;
    if (slope > worst.slope) worst = {slope, p, d};
  }
  return worst;
}

// Largest |f(a) - f(b)| / |a - b| over random nearby pairs in [lo, hi].
template <class Field>
double measured_slope(const Field& f, glm::dvec3 lo, glm::dvec3 hi, int pairs = 20000, double step = 1e-5,
                      unsigned seed = 2) {
  return steepest_pair(f, lo, hi, pairs, step, seed).slope;
}

}  // namespace marchcheck::sdf
