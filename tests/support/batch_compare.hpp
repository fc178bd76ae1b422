// The batched tape against the one-point tape, bit for bit, for tests of the batch and of every operator.
#pragma once

#include "marchcheck/sdf/tape.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace marchcheck::testing {

// Points of the box the scenes live in, with a few batch lengths that leave partial vector registers.
template <class T>
std::vector<glm::vec<3, T>> batch_points(int count) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  std::vector<glm::vec<3, T>> v(static_cast<size_t>(count));
  for (auto& p : v) p = glm::vec<3, T>(glm::dvec3(u(rng), u(rng) * 0.5 + 1, u(rng)));
  return v;
}

inline bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
inline bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// How many points evaluate_batch / sample_batch (batch_tape) and evaluate / sample (point_tape) disagree on
// (values or materials; NaN equal to NaN only when the bits match), over batches of kBatch, 37 and 1 points.
template <class T>
int mismatches(const sdf::Tape& batch_tape, const sdf::Tape& point_tape) {
  const auto pts = batch_points<T>(sdf::kBatch + 37 + 1);
  int bad = 0;
  size_t at = 0;
  for (int n : {sdf::kBatch, 37, 1}) {
    T x[sdf::kBatch], y[sdf::kBatch], z[sdf::kBatch], f[sdf::kBatch];
    for (int i = 0; i < n; ++i) {
      x[i] = pts[at + static_cast<size_t>(i)].x;
      y[i] = pts[at + static_cast<size_t>(i)].y;
      z[i] = pts[at + static_cast<size_t>(i)].z;
    }
    int material[sdf::kBatch];
    sdf::evaluate_batch(batch_tape, x, y, z, f, n);
    for (int i = 0; i < n; ++i) bad += !same_bits(f[i], sdf::evaluate(point_tape, pts[at + static_cast<size_t>(i)]));
    sdf::sample_batch(batch_tape, x, y, z, f, material, n);
    for (int i = 0; i < n; ++i) {
      const sdf::Sample<T> one = sdf::sample(point_tape, pts[at + static_cast<size_t>(i)]);
      bad += !same_bits(f[i], one.distance) || material[i] != one.material;
    }
    at += static_cast<size_t>(n);
  }
  return bad;
}

}  // namespace marchcheck::testing
