#include "marchcheck/march/packet.hpp"

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <limits>

namespace marchcheck::march {

namespace {

constexpr int kMaxPacket = 256;  // rays in flight at once: one render tile

// A packet of rays as structure of arrays, so that the bookkeeping of a step, not only the evaluation, runs as
// vectorised loops. Rays that end stay in place, masked, until half the packet has ended; then the packet is
// compacted (at a quarter, an eighth, or 16 lanes, lee-flat rendered 1-5% slower: compaction costs more than
// masked lanes).
// Integers as wide as T, so a loop mixing them with T vectorises.
template <class T>
using Int = std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>;

// How the lanes step: SphereTrace's rule (sphere and scaled marchers), with over-relaxation (relaxed), or
// FixedTrace's steps and bisection (fixed).
enum class Rule { sphere, relaxed, fixed };

template <class T>
struct Lanes {
  alignas(64) T ox[kMaxPacket], oy[kMaxPacket], oz[kMaxPacket], dx[kMaxPacket], dy[kMaxPacket], dz[kMaxPacket];
  // last_f: the field where the lane ended (signed: a hit's secant root needs it).
  alignas(64) T t[kMaxPacket], max_dist[kMaxPacket], min_abs[kMaxPacket], t_at_min[kMaxPacket], last_f[kMaxPacket];
  alignas(64) Int<T> steps[kMaxPacket], code[kMaxPacket], id[kMaxPacket];
  // The last forward step's start and f (the relaxed marcher's fallback, the secant's other sample); the relaxed
  // marcher's factor (1 once it stepped back).
  alignas(64) T prev_t[kMaxPacket], prev_f[kMaxPacket], omega[kMaxPacket];
  // Rule::fixed: the bracket being bisected (while stepping, lo is the last step's start), and whether it is.
  alignas(64) T lo[kMaxPacket], hi[kMaxPacket];
  alignas(64) Int<T> bisecting[kMaxPacket];
  // Scratch of one step (never compacted): the points and the field's values there.
  alignas(64) T x[kMaxPacket], y[kMaxPacket], z[kMaxPacket], f[kMaxPacket];
};

// HitRefine::secant: the hits whose secant root is still to be evaluated, one evaluation after the lanes ended (as
// SphereTrace's extra step): their records, roots and the points there.
template <class T>
struct SecantRoots {
  int count = 0;
  alignas(64) int id[kMaxPacket];
  alignas(64) T t[kMaxPacket], x[kMaxPacket], y[kMaxPacket], z[kMaxPacket], f[kMaxPacket];
};

constexpr int kRunning = -1;  // else the Outcome

// The part of a step every rule shares, detail::Tracker::saw and end: lane i saw v at t and wants `code` (already
// kRunning, or how it ends). A lane that had ended keeps its code; its code, steps and last f change only when it
// ends (so compaction need not move them for running lanes). Returns whether lane i was running.
// Every array is stored whole, a blend of its old and new values, the new values computed first: GCC turns
// `a[i] = c ? x : a[i]` into a masked store skipped when no lane changes, a branch as unpredictable as a lane's end.
template <class T>
inline bool settle(Lanes<T>& l, int i, Int<T>& code, T v, T t, T a, Int<T> steps) {
  const Int<T> old = l.code[i], old_steps = l.steps[i];
  const T old_min = l.min_abs[i], old_t_at_min = l.t_at_min[i], old_last = l.last_f[i];
  const bool live = old == kRunning;
  const bool better = live && a < old_min;
  code = live ? code : old;
  const bool ends = code != old;
  const T t_at_min = better ? t : old_t_at_min, min_abs = better ? a : old_min, last = ends ? v : old_last;
  const Int<T> steps_now = ends ? steps : old_steps;
  l.t_at_min[i] = t_at_min;
  l.min_abs[i] = min_abs;
  l.steps[i] = steps_now;
  l.last_f[i] = last;
  l.code[i] = code;
  return live;
}

// SphereTrace::feed for every lane at once (Relaxed: with its over-relaxation and step back, else omega = 1;
// Secant: keeping the samples a hit's secant root is taken from); the same expressions in the same order. All
// lanes of a packet start together, so a running lane's step count is the packet's: `step` (this evaluation's
// number). Every lane loads and computes every outcome, then selects (`&`, not `&&`): a load or an addition made
// conditional does not vectorise. Returns the number of lanes still running.
// Perturbed: the rule has a perturbation's width; without one (+inf), its step and radii are the plain terms, bit
// for bit, and the lanes skip the perturbed terms (the relaxed marcher takes four steps' worth a lane: half its
// arithmetic).
template <bool First, bool Relaxed, bool Secant, bool Perturbed, class T>
int feed_lanes(Lanes<T>& l, int count, int step, const StepRule<T> rule, T eps_at_0, T eps_slope, int max_steps) {
  using I = Int<T>;
  const auto step_of = [&rule](T v, T omega) {
    if constexpr (Perturbed) return rule.step(v, omega);
    else return rule.plain_step(v, omega);
  };
  const auto radii = [&rule](T a, T b) {
    if constexpr (Perturbed) return rule.radii(a, b);
    else return rule.plain_radii(a, b);
  };
  const T largest = std::numeric_limits<T>::max();
  const I running = kRunning, miss_far = I(Outcome::miss_far), hit = I(Outcome::hit), inside = I(Outcome::inside),
          invalid = I(Outcome::invalid);
  const I out_of_steps = step >= max_steps ? I(Outcome::miss_steps) : running;
  I still = 0;
  for (int i = 0; i < count; ++i) {
    const T v = l.f[i], t = l.t[i], a = std::abs(v);
    const T eps = eps_at_0 + eps_slope * t;  // hit_threshold: each mode is a + b t with an exact zero term
    bool back = false;
    T forward_step = step_of(v, T(1)), next = t + forward_step;
    T prev_t = 0, prev_f = 0, omega = 1;
    if constexpr (Relaxed || Secant) {
      prev_t = l.prev_t[i];
      prev_f = l.prev_f[i];
    }
    if constexpr (Relaxed) {
      // Where the two unbounding spheres do not overlap, back to the last forward step's start, then omega 1.
      // The last step's length, SphereTrace's prev_step, is rule.step(prev_f, omega) bit for bit: a forward step
      // is rule.step(v, omega) with omega unchanged, a step back rule.step(prev_f, 1) with omega 1 from then on.
      omega = l.omega[i];
      const T reach = radii(a, prev_f), prev_step = step_of(prev_f, omega),
              back_to = prev_t + step_of(prev_f, T(1));
      back = (omega > T(1)) & (reach < prev_step);
      forward_step = step_of(v, omega);
      const T ahead = t + forward_step;
      next = back ? back_to : ahead;
    }
    // As SphereTrace: past max_dist where a plain step passes it too (an over-relaxed one may yet step back).
    // One select per condition: the three combined in one condition kept GCC from vectorising the loop.
    const T plain_reach = t + step_of(v, T(1));
    const T md = l.max_dist[i];
    I code = out_of_steps;
    code = next > md ? miss_far : code;
    code = plain_reach > md ? code : out_of_steps;
    code = back ? out_of_steps : code;
    const I moved = code;  // t moves on unless the step below ends the ray where it is
    code = !back && v < eps ? hit : code;
    if constexpr (First) code = v < -eps ? inside : code;
    code = a <= largest ? code : invalid;  // not finite
    const bool live = settle(l, i, code, v, t, a, I(step));
    const T t_next = live && code == moved ? next : t;
    l.t[i] = t_next;
    if constexpr (Relaxed || Secant) {
      const bool forward = live && code == moved && !back;  // a step taken: the next one's fallback
      if constexpr (Relaxed) l.omega[i] = back ? T(1) : omega;
      l.prev_t[i] = forward ? t : prev_t;
      l.prev_f[i] = forward ? v : prev_f;
    }
    still += code == running;
  }
  return static_cast<int>(still);
}

// FixedTrace::feed for every lane at once: steps of fixed_step; a step that lands inside (f below -threshold)
// bisects the bracket from the previous point until |f| is below the threshold at its midpoint or the bracket
// cannot shrink. The same expressions as FixedTrace. While stepping, lo is FixedTrace's prev_t, so that a step
// that lands inside updates the bracket as a bisection does (v < -threshold <= 0: t becomes hi) and one rule
// serves both: every select has one condition (GCC vectorises no select nested in another's arm).
template <bool First, class T>
int feed_fixed_lanes(Lanes<T>& l, int count, int step, T fixed_step, T eps_at_0, T eps_slope, int max_steps) {
  using I = Int<T>;
  const T largest = std::numeric_limits<T>::max();
  const I running = kRunning, miss_far = I(Outcome::miss_far), hit = I(Outcome::hit), inside = I(Outcome::inside),
          invalid = I(Outcome::invalid);
  const bool last_step = step >= max_steps;
  const I out_of_steps = last_step ? I(Outcome::miss_steps) : running;
  I still = 0;
  for (int i = 0; i < count; ++i) {
    const T v = l.f[i], t = l.t[i], a = std::abs(v), lo = l.lo[i], hi = l.hi[i];
    const T eps = eps_at_0 + eps_slope * t;  // hit_threshold at the point evaluated, a step's or a midpoint
    const bool bisecting = l.bisecting[i] != 0, finite = a <= largest;
    // Bisecting: t is the bracket's midpoint; it ends there, or the side of the same sign as v moves to it.
    const bool bisect_hit = (a < eps) | !((t > lo) & (t < hi));
    // Stepping: below the threshold is a hit, unless the step went past the surface (below -threshold after the
    // first step): then bisect [lo, t].
    const bool below = v < eps, step_hit = below & ((v > -eps) | First), inside_first = First & (v < -eps);
    const bool ends_here = (bisecting & bisect_hit) | (!bisecting & step_hit);
    const bool splits = (bisecting & !bisect_hit) | (!bisecting & below & !step_hit);
    const bool forward = !bisecting & !below, above = v > 0;
    const T lo_next = (above | forward) ? t : lo, hi_next = above ? hi : t;
    const T mid = lo_next + (hi_next - lo_next) * T(0.5), ahead = t + fixed_step;
    I code = (!splits & (ahead > l.max_dist[i])) ? miss_far : out_of_steps;
    code = ends_here ? hit : code;
    code = inside_first ? inside : code;
    code = finite ? code : invalid;
    T t_next = splits ? mid : ahead;  // where the field is wanted next, or where the ray ends
    t_next = (splits & last_step) ? lo_next : t_next;
    t_next = (ends_here | inside_first | !finite) ? t : t_next;
    const bool live = settle(l, i, code, v, t, a, I(step));
    l.t[i] = live ? t_next : t;
    // A lane that ended never reads these again.
    l.lo[i] = lo_next;
    l.hi[i] = hi_next;
    l.bisecting[i] = I(splits);
    still += code == running;
  }
  return static_cast<int>(still);
}

// Writes the records of the lanes that ended (Secant: a hit with a step left and a secant root apart from where it
// stopped joins `roots`) and packs the running ones to the front; returns their count.
// Branch-free index lists first, then one plain loop per array: a lane's fate is not predictable.
template <Rule R, bool Secant, class T>
int compact(Lanes<T>& l, int count, RayRecord<T>* records, int max_steps, SecantRoots<T>& roots) {
  int keep[kMaxPacket], ended[kMaxPacket];
  int kept = 0, done = 0;
  for (int i = 0; i < count; ++i) {
    const bool running = l.code[i] == kRunning;
    keep[kept] = i;
    ended[done] = i;
    kept += running;
    done += !running;
  }
  for (int e = 0; e < done; ++e) {
    const int i = ended[e];
    RayRecord<T>& r = records[l.id[i]];
    r.outcome = static_cast<Outcome>(l.code[i]);
    r.t = l.t[i];
    r.steps = r.evals = static_cast<int>(l.steps[i]);
    r.min_abs_f = l.min_abs[i];
    r.t_at_min = l.t_at_min[i];
    r.last_abs_f = std::abs(l.last_f[i]);
    if constexpr (Secant) {
      const T root = secant_root(l.prev_t[i], l.prev_f[i], r.t, l.last_f[i]);
      if (r.outcome == Outcome::hit && r.steps > 1 && r.steps < max_steps && root != r.t) {
        const int k = roots.count++;
        roots.id[k] = static_cast<int>(l.id[i]);
        roots.t[k] = root;
        // As the lanes' points: origin + direction * t.
        roots.x[k] = l.ox[i] + l.dx[i] * root;
        roots.y[k] = l.oy[i] + l.dy[i] * root;
        roots.z[k] = l.oz[i] + l.dz[i] * root;
      }
    }
  }
  // In place: keep[k] >= k and rises, so each entry is read before it is overwritten.
  int first = 0;  // the lanes before the first ended one stay where they are
  while (first < kept && keep[first] == first) ++first;
  const auto move = [&](auto* a) {
    for (int k = first; k < kept; ++k) a[k] = a[keep[k]];
  };
  // A running lane's steps and last f are not kept yet (settle), and its code is kRunning.
  for (T* a : {l.ox, l.oy, l.oz, l.dx, l.dy, l.dz, l.t, l.max_dist, l.min_abs, l.t_at_min}) move(a);
  if constexpr (R == Rule::relaxed || Secant) {
    move(l.prev_t);
    move(l.prev_f);
  }
  if constexpr (R == Rule::relaxed) move(l.omega);
  if constexpr (R == Rule::fixed) {
    move(l.lo);
    move(l.hi);
    move(l.bisecting);
  }
  move(l.id);
  std::fill_n(l.code + first, kept - first, Int<T>(kRunning));
  return kept;
}

// Marches rays[ids[i]] over spans[i] (clip_span's) into records[ids[i]], i < n <= kMaxPacket, by rule R.
template <Rule R, bool Secant, class T>
void march_lanes(const sdf::Tape& tape, const PacketRay<T>* rays, const int* ids, const Span<T>* spans, int n,
                 RayRecord<T>* records, const MarchSettings& s, const MarchContext& c) {
  Lanes<T> l;
  SecantRoots<T> roots;
  std::fill_n(l.min_abs, n, std::numeric_limits<T>::infinity());
  std::fill_n(l.last_f, n, std::numeric_limits<T>::infinity());
  std::fill_n(l.t_at_min, n, T(0));
  std::fill_n(l.code, n, Int<T>(kRunning));
  for (T* a : {l.prev_f, l.hi}) std::fill_n(a, n, T(0));
  std::fill_n(l.omega, n, T(s.relaxation));
  std::fill_n(l.bisecting, n, Int<T>(0));
  for (int i = 0; i < n; ++i) {
    const PacketRay<T>& ray = rays[ids[i]];
    l.ox[i] = ray.origin.x;
    l.oy[i] = ray.origin.y;
    l.oz[i] = ray.origin.z;
    l.dx[i] = ray.direction.x;
    l.dy[i] = ray.direction.y;
    l.dz[i] = ray.direction.z;
    // As march(): from the start of the ray's span (the traces' t and their last step's start), to its end.
    l.t[i] = l.prev_t[i] = l.lo[i] = spans[i].t0;
    l.max_dist[i] = spans[i].t1;
    l.id[i] = ids[i];
  }
  const StepRule<T> rule(s, c);
  const bool perturbed = rule.width < std::numeric_limits<T>::infinity();
  const T eps_at_0 = s.eps_mode == EpsMode::absolute ? T(s.hit_eps)
                     : s.eps_mode == EpsMode::pixel  ? T(c.footprint_at_0)
                                                     : T(0);
  const T eps_slope = s.eps_mode == EpsMode::relative ? T(s.hit_eps)
                      : s.eps_mode == EpsMode::pixel  ? T(c.footprint_slope)
                                                      : T(0);
  const auto feed = [&](auto first, int count, int step) {
    constexpr bool First = decltype(first)::value;
    if constexpr (R == Rule::fixed)
      return feed_fixed_lanes<First>(l, count, step, T(s.fixed_step), eps_at_0, eps_slope, s.max_steps);
    else if (perturbed)
      return feed_lanes<First, R == Rule::relaxed, Secant, true>(l, count, step, rule, eps_at_0, eps_slope,
                                                                  s.max_steps);
    else
      return feed_lanes<First, R == Rule::relaxed, Secant, false>(l, count, step, rule, eps_at_0, eps_slope,
                                                                   s.max_steps);
  };
  int count = n;
  for (int step = 1; count > 0; ++step) {
    for (int i = 0; i < count; ++i) {
      // As march(): origin + direction * t.
      l.x[i] = l.ox[i] + l.dx[i] * l.t[i];
      l.y[i] = l.oy[i] + l.dy[i] * l.t[i];
      l.z[i] = l.oz[i] + l.dz[i] * l.t[i];
    }
    for (int b = 0; b < count; b += sdf::kBatch)
      sdf::evaluate_batch(tape, l.x + b, l.y + b, l.z + b, l.f + b, std::min(sdf::kBatch, count - b));
    const int running = step == 1 ? feed(std::true_type{}, count, step) : feed(std::false_type{}, count, step);
    if (running == 0 || running < count / 2) count = compact<R, Secant>(l, count, records, s.max_steps, roots);
  }
  if constexpr (Secant) {
    for (int b = 0; b < roots.count; b += sdf::kBatch)
      sdf::evaluate_batch(tape, roots.x + b, roots.y + b, roots.z + b, roots.f + b,
                          std::min(sdf::kBatch, roots.count - b));
    // SphereTrace's step at the root: counted and tracked, and the hit moves there where |f| is smaller.
    for (int k = 0; k < roots.count; ++k) {
      RayRecord<T>& r = records[roots.id[k]];
      const T a = std::abs(roots.f[k]), stopped_abs = r.last_abs_f;
      r.steps = r.evals = r.steps + 1;
      r.last_abs_f = a;
      if (a < r.min_abs_f) {
        r.min_abs_f = a;
        r.t_at_min = roots.t[k];
      }
      if (a < stopped_abs) r.t = roots.t[k];
    }
  }
}

}  // namespace

template <class T>
void march_packet(const sdf::Tape& tape, const PacketRay<T>* rays, RayRecord<T>* records, int n,
                  const MarchSettings& s, const MarchContext& c) {
  const auto one_point = [&tape](glm::vec<3, T> p) { return sdf::evaluate(tape, p); };
  int active[kMaxPacket];
  Span<T> spans[kMaxPacket];
  // settings_invalid reads max_dist only as max_dist > 0: decided once here rather than per ray.
  MarchSettings unit = s;
  unit.max_dist = 1;
  const bool settings_bad = settings_invalid(unit, c) || !(0 < s.max_steps);
  const bool clipped = s.clip != sdf::Clip::none;
  for (int base = 0; base < n; base += kMaxPacket) {
    const int m = std::min(kMaxPacket, n - base);
    int count = 0;
    for (int i = 0; i < m; ++i) {
      const PacketRay<T>& ray = rays[base + i];
      // Rare: one point at a time (with no step allowed, or outside the clip box, march() ends the ray without
      // evaluating). Each ray's span is found once, here (unclipped: all of it, as clip_span gives it).
      const bool marchable =
          (!settings_bad) & (ray.max_dist > 0) & (!detail::ray_degenerate(ray.origin, ray.direction, T(0)));
      Span<T> span{T(0), static_cast<T>(ray.max_dist)};
      if (marchable && clipped) span = clip_span(s, c, ray.origin, ray.direction, T(0), static_cast<T>(ray.max_dist));
      if (!marchable || span.empty()) {
        MarchSettings own = s;
        own.max_dist = ray.max_dist;
        records[base + i] = march<T>(one_point, ray.origin, ray.direction, own, c);
      } else {
        active[count] = i;
        spans[count++] = span;
      }
    }
    const bool relaxed = s.marcher == Marcher::relaxed, secant = s.refine == sdf::HitRefine::secant;
    const auto run = [&](auto path) { path(tape, rays + base, active, spans, count, records + base, s, c); };
    // The fixed marcher's bisection is its own refinement (FixedTrace takes no secant).
    if (s.marcher == Marcher::fixed) run(march_lanes<Rule::fixed, false, T>);
    else if (relaxed && secant) run(march_lanes<Rule::relaxed, true, T>);
    else if (relaxed) run(march_lanes<Rule::relaxed, false, T>);
    else if (secant) run(march_lanes<Rule::sphere, true, T>);
    else run(march_lanes<Rule::sphere, false, T>);
  }
}

template <class T>
void central_normals_packet(const sdf::Tape& tape, const glm::vec<3, T>* points, const T* eps,
                            NormalResult<T>* normals, int n) {
  using V = glm::vec<3, T>;
  for (int base = 0; base < n; base += sdf::kBatch) {
    const int m = std::min(sdf::kBatch, n - base);
    alignas(64) T px[sdf::kBatch], py[sdf::kBatch], pz[sdf::kBatch], e[sdf::kBatch];
    alignas(64) T x[sdf::kBatch], y[sdf::kBatch], z[sdf::kBatch], f[6][sdf::kBatch];
    for (int i = 0; i < m; ++i) {
      px[i] = points[base + i].x;
      py[i] = points[base + i].y;
      pz[i] = points[base + i].z;
      e[i] = eps[base + i];
    }
    // The probes of estimate_normal, one batch per probe in its order: p + V(e, 0, 0), p - V(e, 0, 0), p + V(0, e,
    // 0), ... as glm computes them, zeros included (p.y + 0 turns -0 into +0).
    for (int j = 0; j < 6; ++j) {
      const int axis = j / 2;
      const bool minus = j % 2;
      for (int i = 0; i < m; ++i) {
        const T ex = axis == 0 ? e[i] : T(0), ey = axis == 1 ? e[i] : T(0), ez = axis == 2 ? e[i] : T(0);
        x[i] = minus ? px[i] - ex : px[i] + ex;
        y[i] = minus ? py[i] - ey : py[i] + ey;
        z[i] = minus ? pz[i] - ez : pz[i] + ez;
      }
      sdf::evaluate_batch(tape, x, y, z, f[j], m);
    }
    for (int i = 0; i < m; ++i)
      normals[base + i] = {detail::unit_or_zero(V(f[0][i] - f[1][i], f[2][i] - f[3][i], f[4][i] - f[5][i])), 6};
  }
}

template void march_packet<float>(const sdf::Tape&, const PacketRay<float>*, RayRecord<float>*, int,
                                  const MarchSettings&, const MarchContext&);
template void march_packet<double>(const sdf::Tape&, const PacketRay<double>*, RayRecord<double>*, int,
                                   const MarchSettings&, const MarchContext&);
template void central_normals_packet<float>(const sdf::Tape&, const glm::vec3*, const float*, NormalResult<float>*, int);
template void central_normals_packet<double>(const sdf::Tape&, const glm::dvec3*, const double*, NormalResult<double>*,
                                             int);

}  // namespace marchcheck::march
