// Interval arithmetic and the tape's interval rules. Compiled with -frounding-math: the rounding direction
// changes at run time, and the optimiser must not fold or reorder operations across it.
#include "marchcheck/sdf/interval.hpp"

#include <boost/numeric/interval.hpp>

#include <algorithm>
#include <cfenv>
#include <cmath>
#include <numbers>
#include <string_view>
#include <vector>

namespace marchcheck::sdf {

namespace {

namespace bi = boost::numeric::interval_lib;
using Boost = boost::numeric::interval<double, bi::policies<bi::rounded_math<double>, bi::checking_base<double>>>;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Switching the rounding direction around every operation cost 75% of a certified ray (fesetround and
// fegetround, measured on lee-terrain): an evaluation of the tape rounds upwards throughout instead, as Boost's
// unprotected intervals expect (rounded_arith_opp rounds down by negating), and the operators called outside one
// switch around each operation.
using Unprotected = bi::unprotect<Boost>::type;
thread_local bool t_upward = false;

// The tape evaluated rounding upwards.
class Upward {
 public:
  Upward() : saved_(std::fegetround()) {
    std::fesetround(FE_UPWARD);
    t_upward = true;
  }
  ~Upward() {
    std::fesetround(saved_);
    t_upward = false;
  }
  Upward(const Upward&) = delete;
  Upward& operator=(const Upward&) = delete;

 private:
  int saved_;
};

// glibc's sin, cos and log keep their documented error bound in the default rounding only.
class ToNearest {
 public:
  ToNearest() {
    if (t_upward) std::fesetround(FE_TONEAREST);
  }
  ~ToNearest() {
    if (t_upward) std::fesetround(FE_UPWARD);
  }
  ToNearest(const ToNearest&) = delete;
  ToNearest& operator=(const ToNearest&) = delete;
};

// A bound that is NaN (inf - inf, 0 x inf) proves nothing: the whole line.
Interval safe(double lo, double hi) {
  if (std::isnan(lo) || std::isnan(hi)) return Interval::entire();
  return {lo, hi};
}
template <class B>
Interval from(const B& b) {
  return safe(b.lower(), b.upper());
}

// A Boost operation on two intervals, in the rounding the evaluation has set or switching around it.
template <class Op>
Interval boost_op(Interval a, Interval b, Op op) {
  if (t_upward) return from(op(Unprotected(a.lo, a.hi, true), Unprotected(b.lo, b.hi, true)));
  return from(op(Boost(a.lo, a.hi, true), Boost(b.lo, b.hi, true)));
}
template <class Op>
Interval boost_op(Interval a, Op op) {
  if (t_upward) return from(op(Unprotected(a.lo, a.hi, true)));
  return from(op(Boost(a.lo, a.hi, true)));
}

// glibc documents at most 1 ulp of error for sin, cos and log in double on x86-64 (the manual's "Known Maximum
// Errors in Math Functions"); each bound is moved 4 ulps outwards.
constexpr int kLibmUlps = 4;
double down(double x) {
  for (int i = 0; i < kLibmUlps; ++i) x = std::nextafter(x, -kInf);
  return x;
}
double up(double x) {
  for (int i = 0; i < kLibmUlps; ++i) x = std::nextafter(x, kInf);
  return x;
}

// Whether a holds a point phase + 2 pi k. Past |x| = 1e6 the quotient's rounding is not negligible: say yes. The
// slack makes a point near an end count as inside, which only widens the result.
bool holds_phase(Interval a, double phase) {
  if (!(std::abs(a.lo) < 1e6 && std::abs(a.hi) < 1e6)) return true;
  constexpr double kTurn = 2 * std::numbers::pi, kSlack = 1e-9;
  return std::floor((a.hi - phase) / kTurn + kSlack) >= std::ceil((a.lo - phase) / kTurn - kSlack);
}

// sin or cos over a: the ends' values widened, and +-1 where a holds a maximum or minimum (at max_phase and
// max_phase + pi).
template <double (*F)(double)>
Interval periodic(Interval a, double max_phase) {
  if (!(a.width() < 6)) return {-1, 1};  // wider than a turn or not finite
  const ToNearest nearest;
  const double fa = F(a.lo), fb = F(a.hi);
  const double lo = holds_phase(a, max_phase + std::numbers::pi) ? -1 : std::max(-1.0, down(std::min(fa, fb)));
  const double hi = holds_phase(a, max_phase) ? 1 : std::min(1.0, up(std::max(fa, fb)));
  return {lo, hi};
}
double sin_d(double x) { return std::sin(x); }
double cos_d(double x) { return std::cos(x); }

}  // namespace

Interval& Interval::operator+=(Interval b) { return *this = *this + b; }
Interval& Interval::operator-=(Interval b) { return *this = *this - b; }
Interval& Interval::operator*=(Interval b) { return *this = *this * b; }
Interval& Interval::operator/=(Interval b) { return *this = *this / b; }

Interval operator+(Interval a, Interval b) {
  return boost_op(a, b, [](const auto& x, const auto& y) { return x + y; });
}
Interval operator-(Interval a, Interval b) {
  return boost_op(a, b, [](const auto& x, const auto& y) { return x - y; });
}
Interval operator-(Interval a) { return {-a.hi, -a.lo}; }
Interval operator*(Interval a, Interval b) {
  return boost_op(a, b, [](const auto& x, const auto& y) { return x * y; });
}
Interval operator/(Interval a, Interval b) {
  if (b.contains(0)) return Interval::entire();  // may be a division by zero
  return boost_op(a, b, [](const auto& x, const auto& y) { return x / y; });
}
Interval square(Interval a) {
  return boost_op(a, [](const auto& x) { return boost::numeric::square(x); });
}
Interval sqrt(Interval a) {
  if (!(a.lo >= 0)) return Interval::entire();  // may be the root of a negative: NaN
  return boost_op(a, [](const auto& x) { return boost::numeric::sqrt(x); });
}
Interval abs(Interval a) {
  if (a.lo >= 0) return a;
  if (a.hi <= 0) return -a;
  return {0, std::max(-a.lo, a.hi)};
}
Interval min(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)}; }
Interval max(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)}; }
Interval floor(Interval a) { return {std::floor(a.lo), std::floor(a.hi)}; }
Interval sign(Interval a) {
  auto s = [](double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); };
  return {s(a.lo), s(a.hi)};
}
Interval sin(Interval a) { return periodic<sin_d>(a, std::numbers::pi / 2); }
Interval cos(Interval a) { return periodic<cos_d>(a, 0); }
Interval log(Interval a) {
  if (!(a.lo >= 0)) return Interval::entire();  // may be the logarithm of a negative: NaN
  const ToNearest nearest;
  return {a.lo == 0 ? -kInf : down(std::log(a.lo)), up(std::log(a.hi))};
}
Interval hull(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }

namespace {

glm::vec<3, Interval> hull(glm::vec<3, Interval> a, glm::vec<3, Interval> b) {
  return {hull(a.x, b.x), hull(a.y, b.y), hull(a.z, b.z)};
}
const glm::vec<3, Interval> kAnyGradient(Interval::entire());

// The smallest |x| over a.
double mignitude(Interval a) { return a.contains(0) ? 0 : std::min(std::abs(a.lo), std::abs(a.hi)); }
// x y and x / y rounded up, for the length bounds.
double times_up(double x, double y) { return (Interval(x) * Interval(y)).hi; }
double over_up(double x, double y) { return y > 0 ? (Interval(x) / Interval(y)).hi : kInf; }

}  // namespace

double norm_bound(const glm::vec<3, Interval>& g) {
  Interval s = square(Interval(g.x.magnitude()));
  s += square(Interval(g.y.magnitude()));
  s += square(Interval(g.z.magnitude()));
  return sqrt(s).hi;
}

DualInterval& DualInterval::operator+=(DualInterval b) { return *this = *this + b; }
DualInterval& DualInterval::operator-=(DualInterval b) { return *this = *this - b; }
DualInterval& DualInterval::operator*=(DualInterval b) { return *this = *this * b; }
DualInterval& DualInterval::operator/=(DualInterval b) { return *this = *this / b; }

DualInterval operator+(DualInterval a, DualInterval b) { return {a.v + b.v, a.d + b.d, (Interval(a.n) + Interval(b.n)).hi}; }
DualInterval operator-(DualInterval a, DualInterval b) { return {a.v - b.v, a.d - b.d, (Interval(a.n) + Interval(b.n)).hi}; }
DualInterval operator-(DualInterval a) { return {-a.v, -a.d, a.n}; }
DualInterval operator*(DualInterval a, DualInterval b) {
  return {a.v * b.v, a.d * b.v + b.d * a.v, (Interval(times_up(a.n, b.v.magnitude())) + Interval(times_up(b.n, a.v.magnitude()))).hi};
}
DualInterval operator/(DualInterval a, DualInterval b) {
  const double numerator = (Interval(times_up(a.n, b.v.magnitude())) + Interval(times_up(b.n, a.v.magnitude()))).hi;
  return {a.v / b.v, (a.d * b.v - b.d * a.v) / (b.v * b.v), over_up(numerator, times_up(mignitude(b.v), mignitude(b.v)))};
}
DualInterval sqrt(DualInterval a) {
  const Interval s = sqrt(a.v);
  if (!(s.lo > 0)) return {s, kAnyGradient, kInf};
  return {s, a.d * (Interval(0.5) / s), over_up(a.n, times_up(2, s.lo))};
}
DualInterval abs(DualInterval a) {
  if (a.v.lo >= 0) return a;
  if (a.v.hi <= 0) return -a;
  return {abs(a.v), hull(a.d, -a.d), a.n};
}
DualInterval min(DualInterval a, DualInterval b) {
  if (a.v.hi <= b.v.lo) return a;
  if (b.v.hi <= a.v.lo) return b;
  return {min(a.v, b.v), hull(a.d, b.d), std::max(a.n, b.n)};
}
DualInterval max(DualInterval a, DualInterval b) {
  if (a.v.hi <= b.v.lo) return b;
  if (b.v.hi <= a.v.lo) return a;
  return {max(a.v, b.v), hull(a.d, b.d), std::max(a.n, b.n)};
}
DualInterval floor(DualInterval a) { return DualInterval(floor(a.v)); }
DualInterval sign(DualInterval a) { return DualInterval(sign(a.v)); }
DualInterval sin(DualInterval a) {
  const Interval c = cos(a.v);
  return {sin(a.v), a.d * c, times_up(a.n, c.magnitude())};
}
DualInterval cos(DualInterval a) {
  const Interval s = sin(a.v);
  return {cos(a.v), a.d * -s, times_up(a.n, s.magnitude())};
}
DualInterval hull(DualInterval a, DualInterval b) {
  return {hull(a.v, b.v), hull(a.d, b.d), std::max(a.n, b.n)};
}


}  // namespace marchcheck::sdf

// The interval rules of the kernels that branch on a value, split space into cells or read data: each written
// once over I (Interval or DualInterval) and installed as the kernel's specialisation for both, so the tape runs
// them where it would run the kernel. Every other kernel runs as written, its arithmetic and min, max, abs,
// sqrt, sin and cos taken by the overloads above.
namespace marchcheck::sdf::kernels {

namespace interval_rules {


// The value restricted to [lo, hi] (the part of a box in one cell), its gradient kept.
Interval within(Interval a, double lo, double hi) { return {std::max(a.lo, lo), std::min(a.hi, hi)}; }
DualInterval within(DualInterval a, double lo, double hi) { return {within(a.v, lo, hi), a.d, a.n}; }

// Nothing provable: any value, any gradient.
template <class I>
I anything() {
  if constexpr (std::is_same_v<I, Interval>) {
    return Interval::entire();
  } else {
    return {Interval::entire(), glm::vec<3, Interval>(Interval::entire())};
  }
}

// A branch on a > b: the branch taken where it is decided, else both, joined.
template <class I, class Then, class Else>
I branch(I a, I b, Then then_, Else else_) {
  const Interval x = value_of(a), y = value_of(b);
  if (x.lo > y.hi) return then_();
  if (x.hi <= y.lo) return else_();
  return hull(then_(), else_());
}

template <class I>
I ellipsoid(const Args<I>& k, vec3<I> p) {
  const vec3<I> r(k(0), k(1), k(2));
  const I k0 = length(vec3<I>(p.x / r.x, p.y / r.y, p.z / r.z));
  const I smallest = min(r.x, min(r.y, r.z));
  return branch(I(1.0), k0, [&] { return (k0 - I(1.0)) * smallest; }, [&] {
    const I k1 = length(vec3<I>(p.x / (r.x * r.x), p.y / (r.y * r.y), p.z / (r.z * r.z)));
    return k0 * (k0 - I(1.0)) / k1;
  });
}

template <class I>
I octahedron(const Args<I>& k, vec3<I> p) {
  const I s = k(0);
  p = abs(p);
  const I m = p.x + p.y + p.z - s;
  auto edge = [&](vec3<I> q) {
    const I kk = clamp(I(0.5) * (q.z - q.y + s), I(0.0), s);
    return length(vec3<I>(q.x, q.y - s + kk, q.z - kk));
  };
  const I face = m * literal<I>(0.57735026918962576);
  // The chain of three tests: each case where it may be taken.
  const vec3<I> cases[3] = {p, vec3<I>(p.y, p.z, p.x), vec3<I>(p.z, p.x, p.y)};
  const I tests[3] = {I(3.0) * p.x, I(3.0) * p.y, I(3.0) * p.z};
  bool have = false;
  I out = face;
  for (int i = 0; i < 3; ++i) {
    const Interval t = value_of(tests[i]), mv = value_of(m);
    if (t.hi < mv.lo) {  // taken wherever it is reached
      const I e = edge(cases[i]);
      return have ? hull(out, e) : e;
    }
    if (t.lo < mv.hi) {  // may be taken
      out = have ? hull(out, edge(cases[i])) : edge(cases[i]);
      have = true;
    }
  }
  return have ? hull(out, face) : face;
}

template <class I>
I capped_torus(const Args<I>& k, vec3<I> p) {
  const I sx = k(0), cy = k(1), ra = k(2), rb = k(3);
  p.x = abs(p.x);
  const I kk = branch(cy * p.x, sx * p.y, [&] { return p.x * sx + p.y * cy; },
                      [&] { return length(vec2<I>(p.x, p.y)); });
  const I len = length(p);
  return sqrt(max(len * len + ra * ra - I(2.0) * ra * kk, I(0.0))) - rb;
}

template <class I>
I cone(const Args<I>& k, vec3<I> p) {
  const vec2<I> q(k(0), k(1));
  const vec2<I> w(length(vec2<I>(p.x, p.z)), p.y);
  const vec2<I> ea = w - q * clamp(dot(w, q) / dot(q, q), I(0.0), I(1.0));
  const vec2<I> eb = w - q * vec2<I>(clamp(w.x / q.x, I(0.0), I(1.0)), I(1.0));
  const I s = max(-(w.x * q.y - w.y * q.x), -(w.y - q.y));
  // sqrt(min(|ea|^2, |eb|^2)) as the smaller length: a length's gradient stays bounded at 0.
  return min(length(ea), length(eb)) * sign(s);
}

template <class I>
I mandelbulb(const Args<I>& k, vec3<I> p) {
  // Only beyond r = 8, where the kernel is the distance to the ball holding the set, is there a closed rule.
  const I big = max(abs(p.x), max(abs(p.y), abs(p.z)));
  if (!(value_of(big).lo > 8)) return anything<I>();
  const I set_radius = literal<I>(std::pow(2.0, 1.0 / (k.raw(0) - 1)));
  return big * length(p / big) - set_radius;
}

// The distance at the box's centre is exact up to double rounding; |f| is 1-Lipschitz, so over the box it lies
// within the half-diagonal of it, and where that keeps it from 0 the sign is the centre's.
template <class I>
I mesh(const Args<I>& k, vec3<I> p) {
  glm::dvec3 centre, half;
  for (int i = 0; i < 3; ++i) {
    const Interval c = value_of(p[i]);
    if (!std::isfinite(c.lo) || !std::isfinite(c.hi)) return anything<I>();
    centre[i] = 0.5 * c.lo + 0.5 * c.hi;
    half[i] = std::max(c.hi - centre[i], centre[i] - c.lo);
  }
  const double d = k.meshes[k.at]->signed_distance(centre);
  // The rounding of the closest-point search: ~1e-15 of the coordinates' size, taken a thousand times over.
  const double slack = std::nextafter(glm::length(half), kInf) + 1e-12 * (1 + std::abs(d) + glm::length(centre));
  const double u = std::abs(d);
  const Interval value = u > slack ? (d > 0 ? Interval(u - slack, u + slack) : Interval(-u - slack, -u + slack))
                                   : Interval(-u - slack, u + slack);
  if constexpr (std::is_same_v<I, Interval>) {
    return value;
  } else {
    // The distance's gradient is a unit vector: each component within [-1, 1].
    const Interval unit(-1, 1);
    return {value, p.x.d * unit + p.y.d * unit + p.z.d * unit, jacobian_bound(p)};
  }
}

template <class I>
I glsl(const Args<I>&, vec3<I>) {
  return anything<I>();
}

// g - clamp(g, 0, top) as two monotone parts, so that an interval inside [0, top] gives exactly 0.
template <class I>
I past_ends(I g, double top) {
  return min(g, I(0.0)) + max(g - I(top), I(0.0));
}

// The trilinear interpolation over each cell the box meets, joined (at most 64 cells; more prove nothing).
template <class I>
I grid(const Args<I>& k, vec3<I> p) {
  const I cell = k(6);
  const vec3<I> g = (p - vec3<I>(k(3), k(4), k(5))) / cell;
  int n[3], first[3], last[3];
  vec3<I> c, outside;
  for (int i = 0; i < 3; ++i) {
    n[i] = static_cast<int>(k.raw(static_cast<std::uint32_t>(i)));
    const double top = n[i] - 1;
    c[i] = clamp(g[i], I(0.0), I(top));
    outside[i] = past_ends(g[i], top);
    const Interval cv = value_of(c[i]);
    if (!(cv.lo >= 0 && cv.hi <= top)) return anything<I>();  // NaN
    first[i] = std::min(static_cast<int>(cv.lo), n[i] - 2);
    last[i] = std::min(static_cast<int>(cv.hi), n[i] - 2);
  }
  if ((last[0] - first[0] + 1) * (last[1] - first[1] + 1) * (last[2] - first[2] + 1) > 64) return anything<I>();
  const I beyond = length(outside) * cell;
  I out = beyond;
  bool have = false;
  int at[3];
  for (at[2] = first[2]; at[2] <= last[2]; ++at[2])
    for (at[1] = first[1]; at[1] <= last[1]; ++at[1])
      for (at[0] = first[0]; at[0] <= last[0]; ++at[0]) {
        vec3<I> f;
        for (int i = 0; i < 3; ++i) f[i] = within(c[i], at[i], at[i] + 1) - I(static_cast<double>(at[i]));
        auto s = [&](int dx, int dy, int dz) {
          return k(7 + static_cast<std::uint32_t>(at[0] + dx + n[0] * (at[1] + dy + n[1] * (at[2] + dz))));
        };
        const I y0 = mix(mix(s(0, 0, 0), s(1, 0, 0), f.x), mix(s(0, 1, 0), s(1, 1, 0), f.x), f.y);
        const I y1 = mix(mix(s(0, 0, 1), s(1, 0, 1), f.x), mix(s(0, 1, 1), s(1, 1, 1), f.x), f.y);
        const I v = mix(y0, y1, f.z) + beyond;
        out = have ? hull(out, v) : v;
        have = true;
      }
  return out;
}

// A repetition's local coordinate p - c round(p / c) (cells clamped to [-n, n] when limited): exact within one
// cell; over several, the cells' local ranges [-c/2, c/2] joined with the end cells' parts. The gradient is the
// point's: the map is a translation on every cell.
template <class I>
I repeat_axis(I p, double c, double n) {
  // Rounded outwards, the cells' range holds every cell the box's points fall in.
  const Interval P = value_of(p), cells = floor(P / Interval(c) + Interval(0.5));
  const double lo = std::clamp(cells.lo, -n, n), hi = std::clamp(cells.hi, -n, n);
  if (lo == hi) return p - I(c * lo);
  const Interval local(std::min(-0.5 * c, (P - Interval(c) * Interval(lo)).lo),
                       std::max(0.5 * c, (P - Interval(c) * Interval(hi)).hi));
  if constexpr (std::is_same_v<I, Interval>) {
    return local;
  } else {
    return {local, p.d, p.n};
  }
}

template <class I>
vec3<I> p_repeat(const Args<I>& k, vec3<I> p) {
  for (std::uint32_t i = 0; i < 3; ++i)
    if (k.raw(i) > 0) p[i] = repeat_axis(p[i], k.raw(i), std::numeric_limits<double>::infinity());
  return p;
}

template <class I>
vec3<I> p_repeat_limited(const Args<I>& k, vec3<I> p) {
  for (std::uint32_t i = 0; i < 3; ++i)
    if (k.raw(i) > 0) p[i] = repeat_axis(p[i], k.raw(i), k.raw(3 + i));
  return p;
}

// Value noise, cell by cell over at most 16 cells: the smoothstep is monotone on a cell, so its range is its ends'.
// The lattice's values are the double ones: what the reference's field is.
template <class I>
I value_noise(I x, I z, NoiseHash hash) {
  const Interval X = value_of(x), Z = value_of(z);
  const double x0 = std::floor(X.lo), x1 = std::floor(X.hi), z0 = std::floor(Z.lo), z1 = std::floor(Z.hi);
  if (!(std::abs(x0) < 4e18 && std::abs(x1) < 4e18 && std::abs(z0) < 4e18 && std::abs(z1) < 4e18) ||
      (x1 - x0 + 1) * (z1 - z0 + 1) > 16) {
    // Anywhere: values in [0, 1], slopes at most 1.5 (the smoothstep's) times a lattice difference of at most 1.
    if constexpr (std::is_same_v<I, Interval>) {
      return {0, 1};
    } else {
      const Interval slope(-1.5, 1.5);
      return {Interval(0, 1), x.d * slope + z.d * slope, 1.5 * (x.n + z.n) * (1 + 1e-15)};
    }
  }
  auto smoothstep = [](I t) {
    auto s = [](double e) { const Interval u(e); return u * u * (Interval(3) - Interval(2) * u); };
    const Interval tv = value_of(t), v = hull(s(tv.lo), s(tv.hi));
    if constexpr (std::is_same_v<I, Interval>) {
      return v;
    } else {
      const Interval slope = Interval(6) * tv * (Interval(1) - tv);
      return I(v, t.d * slope, (Interval(t.n) * Interval(slope.magnitude())).hi);
    }
  };
  I out(0.0);
  bool have = false;
  for (double ix = x0; ix <= x1; ++ix)
    for (double iz = z0; iz <= z1; ++iz) {
      const I ux = smoothstep(within(x, ix, ix + 1) - I(ix)), uz = smoothstep(within(z, iz, iz + 1) - I(iz));
      const auto cx = static_cast<std::int64_t>(ix), cz = static_cast<std::int64_t>(iz);
      const I a(lattice<double>(hash, cx, cz)), b(lattice<double>(hash, cx + 1, cz));
      const I c(lattice<double>(hash, cx, cz + 1)), d(lattice<double>(hash, cx + 1, cz + 1));
      const I v = mix(mix(a, b, ux), mix(c, d, ux), uz);
      out = have ? hull(out, v) : v;
      have = true;
    }
  return out;
}

}  // namespace interval_rules

// A polynomial smooth minimum's gradient is a convex combination of its operands' (weights 1 - h/2 and h/2):
// within their hull and no longer than the longer, which its own arithmetic cannot see.
template <>
DualInterval polynomial_smooth_min<DualInterval>(DualInterval a, DualInterval b, DualInterval k) {
  const DualInterval either = hull(a, b);
  return {polynomial_smooth_min(a.v, b.v, k.v), either.d, either.n};
}

// The combinations' values as their kernels compute them; the material is no interval's concern.
#define MARCHCHECK_INTERVAL_COMBINATION(name, expression)                                \
  template <>                                                                           \
  Combined<Interval> name<Interval>(const Args<Interval>& k, Interval a, Interval b) {  \
    return {expression, false};                                                         \
  }                                                                                     \
  template <>                                                                           \
  Combined<DualInterval> name<DualInterval>(const Args<DualInterval>& k, DualInterval a, DualInterval b) { \
    return {expression, false};                                                         \
  }
MARCHCHECK_INTERVAL_COMBINATION(min_, ((void)k, min(a, b)))
MARCHCHECK_INTERVAL_COMBINATION(max_, ((void)k, max(a, b)))
MARCHCHECK_INTERVAL_COMBINATION(subtract, ((void)k, max(a, -b)))
MARCHCHECK_INTERVAL_COMBINATION(smooth_min, polynomial_smooth_min(a, b, k(0)))
MARCHCHECK_INTERVAL_COMBINATION(smooth_max, -polynomial_smooth_min(-a, -b, k(0)))
MARCHCHECK_INTERVAL_COMBINATION(smooth_subtract, -polynomial_smooth_min(-a, b, k(0)))
#undef MARCHCHECK_INTERVAL_COMBINATION

// A box's distance is length(max(q, 0)) outside and max_component(q) inside, never both: over a box of points
// that meets its face the gradient is one side's or the other's (their hull), not their sum, which the
// arithmetic of the kernel's expression would give (8 for a face of slope 4, at any box size).
template <>
DualInterval box_distance<DualInterval>(vec3<DualInterval> q) {
  const DualInterval outside = length(max(q, DualInterval(0.0))), inside = min(max_component(q), DualInterval(0.0));
  const Interval corner = max_component(q).v;
  if (corner.lo > 0) return outside;
  if (corner.hi <= 0) return inside;
  const DualInterval either = hull(outside, inside);
  return {outside.v + inside.v, either.d, either.n};
}

// A displacement's term a sin(f x) sin(f y) sin(f z) has a gradient of length at most |a f| (|grad| of the
// product of sines is at most 1: its square, with A = sin^2 f x etc., is AB + BC + CA - 3ABC <= 1 on [0, 1]^3)
// times the point's Jacobian: the box of its gradient over a box of the point wider than its period reaches
// sqrt 3 times that.
template <>
DualInterval displace<DualInterval>(const Args<DualInterval>& k, DualInterval d, vec3<DualInterval> p) {
  const DualInterval f = k(1);
  const DualInterval r = d + k(0) * sin(f * p.x) * sin(f * p.y) * sin(f * p.z);
  const double term = (Interval(std::abs(k.raw(0))) * Interval(std::abs(k.raw(1))) * Interval(jacobian_bound(p))).hi;
  return {r.v, r.d, std::min(r.n, (Interval(d.n) + Interval(term)).hi)};
}

// Every other rule above, installed as its kernel's specialisation for both interval types.
template <class I>
using Scalar = I;
#define MARCHCHECK_INTERVAL_RULE(name, Result)                                                                   \
  template <>                                                                                                    \
  Result<Interval> name<Interval>(const Args<Interval>& k, vec3<Interval> p) {                                  \
    return interval_rules::name(k, p);                                                                           \
  }                                                                                                              \
  template <>                                                                                                    \
  Result<DualInterval> name<DualInterval>(const Args<DualInterval>& k, vec3<DualInterval> p) {                  \
    return interval_rules::name(k, p);                                                                           \
  }
MARCHCHECK_INTERVAL_RULE(ellipsoid, Scalar)
MARCHCHECK_INTERVAL_RULE(octahedron, Scalar)
MARCHCHECK_INTERVAL_RULE(capped_torus, Scalar)
MARCHCHECK_INTERVAL_RULE(cone, Scalar)
MARCHCHECK_INTERVAL_RULE(mandelbulb, Scalar)
MARCHCHECK_INTERVAL_RULE(mesh, Scalar)
MARCHCHECK_INTERVAL_RULE(glsl, Scalar)
MARCHCHECK_INTERVAL_RULE(grid, Scalar)
MARCHCHECK_INTERVAL_RULE(p_repeat, vec3)
MARCHCHECK_INTERVAL_RULE(p_repeat_limited, vec3)
#undef MARCHCHECK_INTERVAL_RULE

}  // namespace marchcheck::sdf::kernels

namespace marchcheck::sdf {

template <>
Interval value_noise<Interval>(Interval x, Interval z, NoiseHash hash) {
  return kernels::interval_rules::value_noise(x, z, hash);
}
template <>
DualInterval value_noise<DualInterval>(DualInterval x, DualInterval z, NoiseHash hash) {
  return kernels::interval_rules::value_noise(x, z, hash);
}

namespace {

using smath::vec3;

constexpr bool pushes_point(TapeOp op) {
  switch (op) {
#define MARCHCHECK_POINT_OP(name, shape) \
  case TapeOp::name: return std::string_view(#shape) == "point";
    MARCHCHECK_TAPE_KERNELS(MARCHCHECK_POINT_OP)
#undef MARCHCHECK_POINT_OP
    default: return false;
  }
}

// The p_pop that ends the child of the point instruction at `at`.
std::size_t matching_pop(const Tape& tape, std::size_t at) {
  int depth = 0;
  for (std::size_t i = at;; ++i) {
    if (pushes_point(tape.code[i].op)) ++depth;
    if (tape.code[i].op == TapeOp::p_pop && --depth == 0) return i;
  }
}

// A repetition over a box that meets two cells along an axis has, as one interval, the whole cell's range, and
// its child's value over that is far wider than over the box: the box is split at the cell faces instead (at
// most two cells per axis, 8 pieces), each piece's local point exact. Empty when the box meets one cell per axis
// (the kernel's rule is exact) or too many.
template <class I>
std::vector<vec3<I>> repeat_pieces(const Tape& tape, const Instr& in, vec3<I> p) {
  const kernels::Args<I> k = tape.args<I>(in);
  std::vector<vec3<I>> pieces{p};
  for (std::uint32_t axis = 0; axis < 3; ++axis) {
    const double c = k.raw(axis);
    if (!(c > 0)) continue;
    const double n = in.op == TapeOp::p_repeat_limited ? k.raw(3 + axis) : std::numeric_limits<double>::infinity();
    const Interval P = value_of(p[axis]);
    const Interval cells = floor(P / Interval(c) + Interval(0.5));
    const double lo = std::clamp(cells.lo, -n, n), hi = std::clamp(cells.hi, -n, n);
    if (lo == hi) {  // one cell: its local point, as the kernel's rule
      for (vec3<I>& piece : pieces) piece[axis] = piece[axis] - I(Interval(c) * Interval(lo));
      continue;
    }
    if (hi - lo > 1 || pieces.size() == 4) return {};
    // The face between the cells, as an interval holding the real one: the pieces overlap across its rounding.
    const Interval face = (Interval(lo) + Interval(0.5)) * Interval(c);
    std::vector<vec3<I>> split;
    for (const vec3<I>& piece : pieces) {
      vec3<I> below = piece, above = piece;
      below[axis] = kernels::interval_rules::within(piece[axis], -std::numeric_limits<double>::infinity(), face.hi) -
                    I(Interval(c) * Interval(lo));
      above[axis] = kernels::interval_rules::within(piece[axis], face.lo, std::numeric_limits<double>::infinity()) -
                    I(Interval(c) * Interval(hi));
      split.push_back(below);
      split.push_back(above);
    }
    pieces = std::move(split);
  }
  return pieces.size() > 1 ? pieces : std::vector<vec3<I>>{};
}

// The tape's instructions [begin, end) over the box p, as the one-point tape runs them, but with a repetition
// that meets two cells run once per piece and the results joined.
template <class I>
I run_intervals(const Tape& tape, std::size_t begin, std::size_t end, vec3<I> p0) {
  I values[kMaxValueStack];
  values[0] = I(0.0);
  int materials[1];
  vec3<I> points[kMaxPointStack];
  int vt = -1, pt = 0;
  points[0] = p0;
  for (std::size_t i = begin; i < end; ++i) {
    const Instr& in = tape.code[i];
    if (in.op == TapeOp::p_repeat || in.op == TapeOp::p_repeat_limited) {
      const std::vector<vec3<I>> pieces = repeat_pieces(tape, in, points[pt]);
      if (!pieces.empty()) {
        const std::size_t pop = matching_pop(tape, i);
        I joined = run_intervals(tape, i + 1, pop, pieces[0]);
        for (std::size_t j = 1; j < pieces.size(); ++j) joined = hull(joined, run_intervals(tape, i + 1, pop, pieces[j]));
        values[++vt] = joined;
        i = pop;
        continue;
      }
    }
    detail::step<I, false>(tape, in, values, materials, vt, points, pt);
  }
  return values[0];
}

}  // namespace

template <>
Interval evaluate<Interval>(const Tape& tape, glm::vec<3, Interval> p) {
  const Upward upward;
  return run_intervals(tape, 0, tape.code.size(), p);
}

template <>
DualInterval evaluate<DualInterval>(const Tape& tape, glm::vec<3, DualInterval> p) {
  const Upward upward;
  return run_intervals(tape, 0, tape.code.size(), p);
}

template <>
glm::vec<3, DualInterval> seeded<Interval>(glm::vec<3, Interval> box) {
  return {DualInterval(box.x, {1.0, 0.0, 0.0}), DualInterval(box.y, {0.0, 1.0, 0.0}),
          DualInterval(box.z, {0.0, 0.0, 1.0})};
}

bool interval_supported(const Tape& tape) {
  return std::none_of(tape.code.begin(), tape.code.end(), [](const Instr& in) { return in.op == TapeOp::glsl; });
}

}  // namespace marchcheck::sdf
