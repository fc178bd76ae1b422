// The march's float transcendentals (vector_math.hpp, SLEEF's): each within SLEEF's stated 1.0 ulp of the double
// result, and every lane of a vectorised loop giving the scalar function's bits. Broken variants: a function one
// ulp off (caught by the ulp measure); a clone of another accuracy or kind than the scalar function
// (vector-math-clone-u35, vector-math-clone-cinz in tests/mutants/vector_math.mut).
#define MARCHCHECK_VECTOR_CLONES  // the loops below call the functions' vector clones, as the batched tape does
#include "marchcheck/sdf/vector_math.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

namespace marchcheck::sdf {
namespace {

// The error of got against the exact value (double's result, exact to far below float's rounding), in units of
// float's last place at the exact value.
double ulps(float got, double exact) {
  if (std::isnan(exact)) return std::isnan(got) ? 0 : INFINITY;
  if (std::isinf(exact)) return got == static_cast<float>(exact) ? 0 : INFINITY;
  const double magnitude = std::max(std::abs(exact), static_cast<double>(std::numeric_limits<float>::min()));
  const double ulp = std::ldexp(1.0, std::ilogb(magnitude) - 23);
  return std::abs(static_cast<double>(got) - exact) / ulp;
}

// Arguments spread over magnitudes (log-uniform in [lo, hi], both signs where negative is allowed), plus zeros.
std::vector<float> arguments(double lo, double hi, bool negative, int count = 200000) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> e(std::log(lo), std::log(hi)), u(0, 1);
  std::vector<float> v{0.0f, -0.0f};
  for (int i = 0; i < count; ++i) {
    const float x = static_cast<float>(std::exp(e(rng)));
    v.push_back(negative && u(rng) < 0.5 ? -x : x);
  }
  return v;
}

double worst(const std::function<float(float)>& f, const std::function<double(double)>& exact,
             const std::vector<float>& xs) {
  double w = 0;
  for (float x : xs) w = std::max(w, ulps(f(x), exact(x)));
  return w;
}

// SLEEF's bound for its u10 functions: 1.0 ulp. Each range is where the march calls the function (sin and cos:
// any angle a scene makes, up to 1e6 radians; log and pow: positive arguments).
constexpr double kBound = 1.0;

TEST(VectorMath, EachFunctionIsWithinOneUlpOfDouble) {
  const auto angles = arguments(1e-30, 1e6, true), unit = arguments(1e-30, 1, true);
  const auto positive = arguments(1e-30, 1e30, false), exponents = arguments(1e-6, 80, true);
  const auto slopes = arguments(1e-30, 1e30, true);
  struct Case {
    const char* name;
    std::function<float(float)> f;
    std::function<double(double)> exact;
    const std::vector<float>& xs;
    double bound = kBound;
  };
  const Case cases[] = {
      {"sin", marchcheck_sinf, [](double x) { return std::sin(x); }, angles},
      {"cos", marchcheck_cosf, [](double x) { return std::cos(x); }, angles},
      {"atan", marchcheck_atanf, [](double x) { return std::atan(x); }, slopes},
      {"acos", marchcheck_acosf, [](double x) { return std::acos(x); }, unit},
      {"log", marchcheck_logf, [](double x) { return std::log(x); }, positive},
      {"exp", marchcheck_expf, [](double x) { return std::exp(x); }, exponents},
      {"floor", marchcheck_floorf, [](double x) { return std::floor(x); }, slopes, 0},  // exact
      {"atan2", [](float y) { return marchcheck_atan2f(y, 0.75f); }, [](double y) { return std::atan2(y, 0.75); }, slopes},
      {"atan2 of x", [](float x) { return marchcheck_atan2f(-0.6f, x); },
       [](double x) { return std::atan2(double{-0.6f}, x); }, slopes},
      {"pow", [](float x) { return marchcheck_powf(x, 7.5f); }, [](double x) { return std::pow(x, 7.5); },
       arguments(1e-5, 1e5, false)},
      {"pow of e", [](float e) { return marchcheck_powf(1.7f, e); }, [](double e) { return std::pow(double{1.7f}, e); },
       exponents},
  };
  for (const Case& c : cases) {
    const double w = worst(c.f, c.exact, c.xs);
    EXPECT_LE(w, c.bound) << c.name;
    std::cout << c.name << ": " << w << " ulp at most\n";
  }
}

TEST(VectorMath, AFunctionOneUlpOffIsCaught) {
  const auto angles = arguments(1e-3, 1e3, true);
  const auto off = [](float x) { return std::nextafter(marchcheck_sinf(x), INFINITY); };
  EXPECT_GT(worst(off, [](double x) { return std::sin(x); }, angles), kBound);
}

// A loop the compiler vectorises through the clones (as the batched tape's), against the scalar function one
// argument at a time, over lengths that leave partial vectors. A NaN is any NaN: its sign and payload are the
// vector unit's (log of a negative number is 0x7fc00000 in one lane, 0xffc00000 in another).
bool same(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) || (std::isnan(a) && std::isnan(b));
}

TEST(VectorMath, EveryLaneGivesTheScalarFunctionsBits) {
  const auto xs = arguments(1e-20, 1e5, true, 4099);
  std::vector<float> lanes(xs.size());
  float (*volatile scalar)(float) = marchcheck_sinf;  // through a pointer: never vectorised
  auto check = [&](auto vectorised, float (*one)(float), const char* name) {
    vectorised(xs.data(), lanes.data(), static_cast<int>(xs.size()));
    scalar = one;
    int differ = 0;
    for (size_t i = 0; i < xs.size(); ++i)
      differ += !same(lanes[i], scalar(xs[i]));
    EXPECT_EQ(differ, 0) << name;
  };
#define MARCHCHECK_LANES(fn)                                                             \
  check([](const float* __restrict x, float* __restrict y, int n) {                    \
          for (int i = 0; i < n; ++i) y[i] = fn(x[i]);                                \
        },                                                                             \
        fn, #fn);
  MARCHCHECK_LANES(marchcheck_sinf)
  MARCHCHECK_LANES(marchcheck_cosf)
  MARCHCHECK_LANES(marchcheck_atanf)
  MARCHCHECK_LANES(marchcheck_acosf)
  MARCHCHECK_LANES(marchcheck_logf)
  MARCHCHECK_LANES(marchcheck_expf)
  MARCHCHECK_LANES(marchcheck_floorf)
#undef MARCHCHECK_LANES
  std::vector<float> pairs(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) pairs[i] = marchcheck_atan2f(xs[i], 0.5f) + marchcheck_powf(0.5f, xs[i]);
  float (*volatile atan2)(float, float) = marchcheck_atan2f;
  float (*volatile pow)(float, float) = marchcheck_powf;
  int differ = 0;
  for (size_t i = 0; i < xs.size(); ++i)
    differ += !same(pairs[i], atan2(xs[i], 0.5f) + pow(0.5f, xs[i]));
  EXPECT_EQ(differ, 0) << "atan2, pow";
}

}  // namespace
}  // namespace marchcheck::sdf
