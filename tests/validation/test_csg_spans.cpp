// The exact caster's interval lists for union, intersection and subtraction of nested, overlapping, touching and
// unbounded spans, against brute-force membership sampled along the line (closed-form inside tests, no caster),
// with each span end's normal checked against the surface it lies on.
#include "marchcheck/validation/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace marchcheck::validation {
namespace {

using glm::dvec3;

// A solid as the caster sees it (a tree) and as the test sees it: membership and the surfaces bounding it, each
// giving its unit gradient at a point on it.
struct Solid {
  sdf::Node node;
  std::function<bool(dvec3)> inside;
  std::vector<std::function<std::optional<dvec3>(dvec3)>> surfaces;
};

Solid ball(dvec3 c, double r) {
  return {sdf::translate(c, sdf::sphere(r)), [=](dvec3 p) { return glm::length(p - c) < r; },
          {[=](dvec3 p) -> std::optional<dvec3> {
            if (std::abs(glm::length(p - c) - r) > 1e-9) return std::nullopt;
            return (p - c) / r;
          }}};
}

Solid box(dvec3 c, dvec3 h) {
  return {sdf::translate(c, sdf::box(h)),
          [=](dvec3 p) {
            const dvec3 q = glm::abs(p - c);
            return q.x < h.x && q.y < h.y && q.z < h.z;
          },
          {[=](dvec3 p) -> std::optional<dvec3> {
            const dvec3 q = p - c;
            for (int i = 0; i < 3; ++i)
              if (std::abs(std::abs(q[i]) - h[i]) < 1e-9) {
                dvec3 n(0);
                n[i] = q[i] > 0 ? 1 : -1;
                return n;
              }
            return std::nullopt;
          }}};
}

// The half-space x < h, unbounded along the line.
Solid below_x(double h) {
  return {sdf::plane({1, 0, 0}, -h), [=](dvec3 p) { return p.x < h; },
          {[=](dvec3 p) -> std::optional<dvec3> {
            if (std::abs(p.x - h) > 1e-9) return std::nullopt;
            return dvec3(1, 0, 0);
          }}};
}

std::vector<std::function<std::optional<dvec3>(dvec3)>> both(const Solid& a, const Solid& b) {
  auto s = a.surfaces;
  s.insert(s.end(), b.surfaces.begin(), b.surfaces.end());
  return s;
}
Solid operator|(const Solid& a, const Solid& b) {
  return {sdf::unite({a.node, b.node}), [=](dvec3 p) { return a.inside(p) || b.inside(p); }, both(a, b)};
}
Solid operator&(const Solid& a, const Solid& b) {
  return {sdf::intersect(a.node, b.node), [=](dvec3 p) { return a.inside(p) && b.inside(p); }, both(a, b)};
}
Solid operator-(const Solid& a, const Solid& b) {
  return {sdf::subtract(a.node, b.node), [=](dvec3 p) { return a.inside(p) && !b.inside(p); }, both(a, b)};
}

// Spans sorted and disjoint; every sample of the line away from a span end (1e-6) inside a span exactly when the
// solid holds it; every finite end on one of the solid's surfaces with the normal pointing out of the solid.
void expect_spans_match(const Solid& solid, const std::string& name) {
  SCOPED_TRACE(name);
  const dvec3 o(-6, 0.1, 0.05), d(1, 0, 0);
  const Spans spans = cast_exact(solid.node, o, d);
  for (size_t i = 1; i < spans.size(); ++i) EXPECT_LE(spans[i - 1].t1, spans[i].t0) << "span " << i;
  for (double t = -12; t <= 12; t += 1e-3) {
    bool near_end = false, in_span = false;
    for (const Span& s : spans) {
      near_end = near_end || std::abs(t - s.t0) < 1e-6 || std::abs(t - s.t1) < 1e-6;
      in_span = in_span || (s.t0 < t && t < s.t1);
    }
    // Where membership changes within 1e-6 the line is on a surface (two faces touching, say): no verdict.
    const bool on_surface = solid.inside(o + d * (t - 1e-6)) != solid.inside(o + d * (t + 1e-6));
    if (near_end || on_surface) continue;
    ASSERT_EQ(in_span, solid.inside(o + d * t)) << "t = " << t;
  }
  const auto outward = [&](double t, dvec3 n, const char* end) {
    if (!std::isfinite(t)) return;
    const dvec3 p = o + d * t;
    std::optional<dvec3> g;
    for (const auto& surface : solid.surfaces)
      if (!g) g = surface(p);
    ASSERT_TRUE(g) << end << " at t = " << t << " is on no surface";
    // Out of the solid along the normal, into it against it.
    const dvec3 expected = !solid.inside(p + *g * 1e-6) && solid.inside(p - *g * 1e-6) ? *g : -*g;
    EXPECT_NEAR(glm::length(n - expected), 0, 1e-9) << end << " at t = " << t;
  };
  for (const Span& s : spans) {
    outward(s.t0, s.n0, "entry");
    outward(s.t1, s.n1, "exit");
  }
}

// Broken variants: a union whose nested span shortens the outer one, an intersection or subtraction taking the
// normal of the wrong span's end, a subtraction whose complement starts at the first span instead of -inf.
TEST(CsgSpans, NestedOverlappingTouchingAndUnboundedAgreeWithBruteForce) {
  const Solid outer = ball({0, 0, 0}, 2), inner = ball({0.5, 0, 0}, 0.5);
  const Solid left = ball({0, 0, 0}, 1), right = ball({1.5, 0, 0}, 1);
  const Solid touch_a = ball({-0.5, 0, 0}, 0.5), touch_b = ball({0.5, 0, 0}, 0.5);
  const std::vector<std::pair<std::string, Solid>> cases = {
      {"nested union", outer | inner},
      {"nested union, inner first", inner | outer},
      {"nested intersection", outer & inner},
      {"nested subtraction: a hole", outer - inner},
      {"inner minus outer: nothing", inner - outer},
      {"overlapping union", left | right},
      {"overlapping intersection", left & right},
      {"overlapping subtraction", left - right},
      {"overlapping subtraction, other way", right - left},
      {"balls side by side: union", touch_a | touch_b},
      {"balls side by side: subtraction", touch_a - touch_b},
      {"touching boxes: union", box({-0.5, 0, 0}, dvec3(0.5)) | box({0.5, 0, 0}, dvec3(0.5))},
      {"touching boxes: intersection", box({-0.5, 0, 0}, dvec3(0.5)) & box({0.5, 0, 0}, dvec3(0.5))},
      {"touching boxes: subtraction", box({-0.5, 0, 0}, dvec3(0.5)) - box({0.5, 0, 0}, dvec3(0.5))},
      {"a box in a box: subtraction", box({0, 0, 0}, dvec3(2)) - box({0.5, 0, 0}, dvec3(0.5))},
      {"three: a union with a hole", (ball({-1, 0, 0}, 1) | ball({1, 0, 0}, 1)) - ball({0, 0, 0}, 0.3)},
      {"two holes in one span", outer - ball({-1, 0, 0}, 0.4) - ball({1, 0, 0}, 0.4)},
      {"half-space and ball", below_x(0.5) & outer},
      {"ball minus half-space", outer - below_x(0)},
      {"half-space union a ball beyond it", below_x(0.5) | ball({3, 0, 0}, 1)},
      {"half-space minus a ball: a span from -inf", below_x(3) - inner},
  };
  for (const auto& [name, solid] : cases) expect_spans_match(solid, name);
}

}  // namespace
}  // namespace marchcheck::validation
