// Interval evaluation of the tape: for every operator (the list of all of them, each its example), the
// interval over random boxes holds every value and gradient the double tape gives at dense samples of the box,
// and over small boxes it is tight enough to prove something. Each interval rule shown failing broken: the
// mutants sdf-interval-* (tests/mutants/).
#include "marchcheck/sdf/interval.hpp"
#include "marchcheck/sdf/node.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

namespace marchcheck::sdf {
namespace {

constexpr double kTime = 0.7;  // as the every-operator test: animated operators are not the identity

using Box = glm::vec<3, Interval>;

Box box_around(glm::dvec3 c, glm::dvec3 half) {
  return {Interval(c.x - half.x, c.x + half.x), Interval(c.y - half.y, c.y + half.y),
          Interval(c.z - half.z, c.z + half.z)};
}

glm::dvec3 gradient(const Tape& tape, glm::dvec3 p) {
  return evaluate(tape, seeded(p)).d;
}

// The first sample of a box whose value, gradient or gradient length its intervals miss, or "".
std::string first_escape(const Tape& tape, const Box& box, std::mt19937& rng) {
  const Interval f = evaluate(tape, box);
  const DualInterval g = evaluate(tape, seeded(box));
  std::uniform_real_distribution<double> u(0, 1);
  for (int s = 0; s < 48; ++s) {
    glm::dvec3 p;
    for (int i = 0; i < 3; ++i) {
      // The first eight samples are the corners, where an end-point rule is most likely wrong.
      const double t = s < 8 ? ((s >> i) & 1) : u(rng);
      p[i] = box[i].lo + t * (box[i].hi - box[i].lo);
    }
    const double v = evaluate(tape, p);
    const glm::dvec3 d = gradient(tape, p);
    std::ostringstream out;
    out.precision(17);
    if (std::isnan(v)) continue;  // a NaN has no interval to be in
    // The intervals hold the real values; the double tape's own rounding (some tens of operations at ~1e-16
    // each) moves its values by far less than 1e-12 of their size.
    auto holds = [](Interval a, double x) {
      const double slack = 1e-12 * (1 + std::abs(x));
      return a.lo - slack <= x && x <= a.hi + slack;
    };
    if (!holds(f, v) || !holds(g.v, v))
      out << "value " << v << " at (" << p.x << ", " << p.y << ", " << p.z << ") outside [" << f.lo << ", " << f.hi
          << "] (dual [" << g.v.lo << ", " << g.v.hi << "])";
    for (int i = 0; i < 3 && out.str().empty(); ++i)
      if (std::isfinite(d[i]) && !holds(g.d[i], d[i]))
        out << "gradient " << i << " = " << d[i] << " at (" << p.x << ", " << p.y << ", " << p.z << ") outside ["
            << g.d[i].lo << ", " << g.d[i].hi << "]";
    if (out.str().empty() && std::isfinite(glm::length(d)) && !holds(Interval(0, g.n), glm::length(d)))
      out << "gradient length " << glm::length(d) << " at (" << p.x << ", " << p.y << ", " << p.z << ") over its bound "
          << g.n;
    if (!out.str().empty()) return out.str();
  }
  return "";
}

// Every operator's example field, its 2D shapes extruded (as the every-operator test examines them).
Node field_of(Op op) {
  const Node node = example(op);
  return op_info(op).dimension == 2 ? make(Op::extrude, {{"half_depth", {0.3}}}, {node}) : node;
}

struct Containment {
  std::string escape;  // the first value or gradient outside its box's interval
  double worst_ratio = 0;  // over boxes of half-width 1e-3: interval width / (2 L |half diagonal|)
};

// Boxes at random in [-3, 3]^3 (the examples lie in [-2, 2]^3), half-widths from 1e-6 to 3 log-uniformly: from a
// box around one point to one past the ends of a limited repetition.
Containment containment(const Tape& tape, double lipschitz) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  Containment c;
  for (int b = 0; b < 300 && c.escape.empty(); ++b) {
    const glm::dvec3 centre(6 * u(rng) - 3, 6 * u(rng) - 3, 6 * u(rng) - 3);
    glm::dvec3 half;
    for (int i = 0; i < 3; ++i) half[i] = 3 * std::pow(10.0, -6.5 * u(rng));
    c.escape = first_escape(tape, box_around(centre, half), rng);
    const glm::dvec3 small(1e-3);
    const Interval f = evaluate(tape, box_around(centre, small));
    c.worst_ratio = std::max(c.worst_ratio, f.width() / (2 * lipschitz * glm::length(small)));
  }
  return c;
}

class IntervalOfEveryOperator : public ::testing::TestWithParam<Op> {};

TEST_P(IntervalOfEveryOperator, HoldsEveryValueAndGradientOfItsBoxAndIsTightOnSmallOnes) {
  const Node field = field_of(GetParam());
  const Tape tape = compile(field, kTime);
  const FieldInfo info = derive_info(field, kTime);
  const Containment c = containment(tape, info.lipschitz);
  EXPECT_EQ(c.escape, "");
  if (GetParam() == Op::glsl) {
    EXPECT_FALSE(interval_supported(tape));  // no interval rule: the whole line, which proves nothing
  } else if (GetParam() != Op::mandelbulb) {  // the fractal has a rule only beyond r = 8
    EXPECT_TRUE(interval_supported(tape));
    // Over a box of half-width h a field of Lipschitz constant L varies by at most 2 L |h|; the interval's
    // dependency on repeated variables widens that by a factor the expression sets (measured: 8.2 for the capped
    // torus, at most 2.8 for every other example). 16 leaves room; a rule that proves nothing (the whole line),
    // or a repetition joined over whole cells (86 before the split at cell faces), fails it.
    EXPECT_LT(c.worst_ratio, 16);
  }
}

INSTANTIATE_TEST_SUITE_P(All, IntervalOfEveryOperator, ::testing::ValuesIn(all_ops()),
                         [](const auto& param) { return std::string(op_info(param.param).name); });

// Over three cells and on past the last one, a limited repetition's point runs far beyond half a cell: at
// x = -5 it is -4 (period 1, cells -1 to 1), where the sphere's distance is 3.7.
TEST(Interval, ALimitedRepetitionHoldsItsEndCellsRunningOn) {
  const Node node = make(Op::repeat_limited, {{"period", {1, 0, 0}}, {"count", {1, 0, 0}}}, {sphere(0.3)});
  const Tape tape = compile(node);
  const Box box{Interval(-5, 1), Interval(-0.1, 0.1), Interval(-0.1, 0.1)};
  EXPECT_GE(evaluate(tape, box).hi, 3.7);
  std::mt19937 rng(4);
  EXPECT_EQ(first_escape(tape, box, rng), "");
}

// A displacement read at a stretched point (a scale by 1/2 inside: the point doubled) is twice as steep as
// at the point itself; its gradient bound must follow the stretch.
TEST(Interval, ADisplacementOfAStretchedPointBoundsItsGradient) {
  const Node node = make(Op::scale, {{"factor", {0.5}}}, {example(Op::displace)});
  const Tape tape = compile(node);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(0, 1);
  for (int b = 0; b < 200; ++b) {
    const glm::dvec3 centre(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1);
    ASSERT_EQ(first_escape(tape, box_around(centre, glm::dvec3(std::pow(10.0, -3 * u(rng)))), rng), "");
  }
}

// sin and cos on intervals that hold a maximum, a minimum, both, or neither, and far from 0.
TEST(Interval, SinAndCosHoldTheirExtremaAndEnds) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 20000; ++i) {
    const double lo = (u(rng) - 0.5) * 2e3, w = std::pow(10.0, -8 + 9 * u(rng));
    const Interval a(lo, lo + w), s = sin(a), c = cos(a);
    for (int j = 0; j <= 64; ++j) {
      const double x = lo + w * j / 64;
      ASSERT_TRUE(s.contains(std::sin(x))) << "sin over [" << a.lo << ", " << a.hi << "] at " << x;
      ASSERT_TRUE(c.contains(std::cos(x))) << "cos over [" << a.lo << ", " << a.hi << "] at " << x;
    }
  }
  // The ends against long double (64-bit mantissa: its error is ~1/2048 of a double's ulp): a bound of glibc's
  // double result not moved outwards is on the wrong side of the real value about half the time.
  for (int i = 0; i < 2000; ++i) {
    const double lo = (u(rng) - 0.5) * 20, hi = lo + 1e-3;
    const double pos = lo + 10.5;  // positive, for the logarithm
    const Interval s = sin(Interval(lo, hi)), c = cos(Interval(lo, hi)), l = log(Interval(pos, pos + 1e-3));
    for (const double x : {lo, hi}) {
      const long double xl = x;
      ASSERT_TRUE(s.lo <= sinl(xl) && sinl(xl) <= s.hi) << "sin over [" << lo << ", " << hi << "] at " << x;
      ASSERT_TRUE(c.lo <= cosl(xl) && cosl(xl) <= c.hi) << "cos over [" << lo << ", " << hi << "] at " << x;
    }
    ASSERT_TRUE(l.lo <= logl(pos) && logl(pos + 1e-3) <= l.hi) << "log over [" << pos << ", " << pos + 1e-3 << "]";
  }
  // Exact facts: over [0, pi] sin reaches 1 inside and cos -1 at an end.
  EXPECT_EQ(sin(Interval(0, 3.2)).hi, 1);
  EXPECT_EQ(cos(Interval(0, 3.2)).lo, -1);
  EXPECT_LT(sin(Interval(0, 1)).hi, std::sin(1.0) + 1e-15);  // no extremum inside: the ends, widened 4 ulps
}

// Outward rounding: 0.1 + 0.2 is not a double; the interval holds the real sum, which lies between two.
TEST(Interval, ArithmeticIsRoundedOutwards) {
  const Interval s = Interval(0.1) + Interval(0.2);
  EXPECT_LT(s.lo, s.hi);
  EXPECT_TRUE(s.contains(0.1 + 0.2));
  const Interval third = Interval(1) / Interval(3);
  EXPECT_LT(third.lo, third.hi);
  EXPECT_TRUE((third * Interval(3)).contains(1));
  EXPECT_TRUE((Interval(1) / Interval(-1, 1)).is_entire());  // may divide by 0
  EXPECT_TRUE(sqrt(Interval(-1, 4)).is_entire());            // may be the root of a negative
  EXPECT_EQ(sqrt(Interval(4, 9)).lo, 2);
}

}  // namespace
}  // namespace marchcheck::sdf
