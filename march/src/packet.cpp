#include "marchcheck/march/packet.hpp"

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <limits>

namespace marchcheck::march {

namespace {

constexpr int kMaxPacket = 256;  // rays in flight at once: one render tile

// The state of a packet of sphere-traced rays (sphere, scaled and relaxed marchers) as structure of arrays, so that the bookkeeping of a step, not only the evaluation, runs as vectorised loops. Rays that end
// stay in place, masked, until half the packet has ended; then the packet is compacted (at a quarter, an eighth,
// or 16 lanes, lee-flat rendered 1-5% slower: compaction costs more than masked lanes).
// Integers as wide as T, so a loop mixing them with T vectorises.
template <class T>
using Int = std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>;

template <class T>
struct Lanes {
  alignas(64) T ox[kMaxPacket], oy[kMaxPacket], oz[kMaxPacket], dx[kMaxPacket], dy[kMaxPacket], dz[kMaxPacket];
  alignas(64) T t[kMaxPacket], max_dist[kMaxPacket], min_abs[kMaxPacket], t_at_min[kMaxPacket], last_abs[kMaxPacket];
  alignas(64) Int<T> steps[kMaxPacket], code[kMaxPacket], id[kMaxPacket];
  // The last forward step's start and f (the relaxed marcher's fallback, the secant's other sample); the relaxed
  // marcher's factor (1 once it stepped back) and that step's length.
  alignas(64) T prev_t[kMaxPacket], prev_f[kMaxPacket], omega[kMaxPacket], prev_step[kMaxPacket];
  // HitRefine::secant: a lane evaluating its secant root (else 0), and where it stopped with what |f|.
  alignas(64) Int<T> refining[kMaxPacket];
  alignas(64) T stopped_t[kMaxPacket], stopped_abs[kMaxPacket];
  // Scratch of one step (never compacted): the points and the field's values there.
  alignas(64) T x[kMaxPacket], y[kMaxPacket], z[kMaxPacket], f[kMaxPacket];
};

constexpr int kRunning = -1;  // else the Outcome

// SphereTrace::feed for every lane at once (Relaxed: with its over-relaxation and step back, else omega = 1;
// Secant: a hit's extra evaluation at the secant root); the same expressions in the same order. All lanes of a
// packet start together, so a running lane's step count is the packet's: `step` (this evaluation's number).
// A lane's code, steps and last |f| change only when it ends (so compaction need not move them for running
// lanes). Returns the number of lanes still running.
template <bool First, bool Relaxed, bool Secant, class T>
int feed_lanes(Lanes<T>& l, int count, int step, T scale, T eps_at_0, T eps_slope, int max_steps) {
  using I = Int<T>;
  const T largest = std::numeric_limits<T>::max();
  const I running = kRunning, miss_far = I(Outcome::miss_far), hit = I(Outcome::hit), inside = I(Outcome::inside),
          invalid = I(Outcome::invalid), steps = step;
  const I out_of_steps = step >= max_steps ? I(Outcome::miss_steps) : running;
  I still = 0;
  for (int i = 0; i < count; ++i) {
    const T v = l.f[i], t = l.t[i], a = std::abs(v);
    const T eps = eps_at_0 + eps_slope * t;  // hit_threshold: each mode is a + b t with an exact zero term
    // Relaxed: where the two unbounding spheres do not overlap, back to the last forward step's start, then omega 1.
    bool back = false;
    T forward_step = v * scale, next = t + forward_step;
    if constexpr (Relaxed) {
      const T omega = l.omega[i], prev_f = l.prev_f[i];
      back = omega > T(1) && a + prev_f < l.prev_step[i];
      forward_step = v * omega * scale;
      next = back ? l.prev_t[i] + prev_f * scale : t + forward_step;
    }
    I code = !back && next > l.max_dist[i] ? miss_far : out_of_steps;
    const I moved = code;  // t moves on unless the step below ends the ray where it is
    code = !back && v < eps ? hit : code;
    if constexpr (First) code = v < -eps ? inside : code;
    code = a <= largest ? code : invalid;  // not finite
    // Every array is stored whole, a blend of its old and new values: GCC turns `a[i] = c ? x : a[i]` into a
    // masked store skipped when no lane changes, a branch as unpredictable as a lane's end.
    const I old = l.code[i], old_steps = l.steps[i];
    const T old_min = l.min_abs[i], old_t_at_min = l.t_at_min[i], old_last = l.last_abs[i];
    const bool live = old == running;
    const bool better = live && a < old_min;
    code = live ? code : old;
    T t_next = live && code == moved ? next : t;
    bool refine_now = false;  // a hit that moves to its secant root for one more evaluation
    if constexpr (Secant) {
      const bool refined = live && l.refining[i] != 0;  // v is the field at the root: a hit, there or where it stopped
      const T root = secant_root(l.prev_t[i], l.prev_f[i], t, v);
      refine_now = live && !refined && code == hit && step > 1 && step < max_steps && root != t;
      code = refined ? hit : refine_now ? running : code;
      t_next = refined ? (a < l.stopped_abs[i] ? t : l.stopped_t[i]) : refine_now ? root : t_next;
      l.stopped_t[i] = refine_now ? t : l.stopped_t[i];
      l.stopped_abs[i] = refine_now ? a : l.stopped_abs[i];
      l.refining[i] = refine_now ? I(1) : l.refining[i];
    }
    const bool ends = code != old;
    // The new values first, then the stores: written as `l.steps[i] = ends ? steps : old_steps`, GCC still finds
    // the masked store.
    const T t_at_min = better ? t : old_t_at_min, min_abs = better ? a : old_min, last = ends ? a : old_last;
    const I steps_now = ends ? steps : old_steps;
    l.t_at_min[i] = t_at_min;
    l.min_abs[i] = min_abs;
    l.t[i] = t_next;
    l.steps[i] = steps_now;
    l.last_abs[i] = last;
    l.code[i] = code;
    if constexpr (Relaxed || Secant) {
      const bool forward = live && code == moved && !back && !refine_now;  // a step taken: the next one's fallback
      const T prev_f = l.prev_f[i];
      if constexpr (Relaxed) {
        l.omega[i] = back ? T(1) : l.omega[i];
        l.prev_step[i] = back ? prev_f * scale : forward ? forward_step : l.prev_step[i];
      }
      l.prev_t[i] = forward ? t : l.prev_t[i];
      l.prev_f[i] = forward ? v : prev_f;
    }
    still += code == running;
  }
  return static_cast<int>(still);
}

// Writes the records of the lanes that ended and packs the running ones to the front; returns their count.
// Branch-free index lists first, then one plain loop per array: a lane's fate is not predictable.
template <bool Relaxed, bool Secant, class T>
int compact(Lanes<T>& l, int count, RayRecord<T>* records) {
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
    r.last_abs_f = l.last_abs[i];
  }
  // In place: keep[k] >= k and rises, so each entry is read before it is overwritten.
  int first = 0;  // the lanes before the first ended one stay where they are
  while (first < kept && keep[first] == first) ++first;
  // A running lane's steps and last |f| are not kept yet (feed_lanes), and its code is kRunning.
  for (T* a : {l.ox, l.oy, l.oz, l.dx, l.dy, l.dz, l.t, l.max_dist, l.min_abs, l.t_at_min})
    for (int k = first; k < kept; ++k) a[k] = a[keep[k]];
  if constexpr (Relaxed || Secant)
    for (T* a : {l.prev_t, l.prev_f})
      for (int k = first; k < kept; ++k) a[k] = a[keep[k]];
  if constexpr (Relaxed)
    for (T* a : {l.omega, l.prev_step})
      for (int k = first; k < kept; ++k) a[k] = a[keep[k]];
  if constexpr (Secant) {
    for (T* a : {l.stopped_t, l.stopped_abs})
      for (int k = first; k < kept; ++k) a[k] = a[keep[k]];
    for (int k = first; k < kept; ++k) l.refining[k] = l.refining[keep[k]];
  }
  for (int k = first; k < kept; ++k) l.id[k] = l.id[keep[k]];
  std::fill_n(l.code + first, kept - first, Int<T>(kRunning));
  return kept;
}

// Marches rays[ids[i]] into records[ids[i]], i < n <= kMaxPacket, for the sphere, scaled and relaxed marchers.
template <bool Relaxed, bool Secant, class T>
void march_lanes(const sdf::Tape& tape, const PacketRay<T>* rays, const int* ids, int n, RayRecord<T>* records,
                 const MarchSettings& s, const MarchContext& c) {
  Lanes<T> l;
  for (int i = 0; i < n; ++i) {
    const PacketRay<T>& ray = rays[ids[i]];
    l.ox[i] = ray.origin.x;
    l.oy[i] = ray.origin.y;
    l.oz[i] = ray.origin.z;
    l.dx[i] = ray.direction.x;
    l.dy[i] = ray.direction.y;
    l.dz[i] = ray.direction.z;
    l.max_dist[i] = static_cast<T>(ray.max_dist);
    l.id[i] = ids[i];
  }
  std::fill_n(l.t, n, T(0));
  std::fill_n(l.min_abs, n, std::numeric_limits<T>::infinity());
  std::fill_n(l.last_abs, n, std::numeric_limits<T>::infinity());
  std::fill_n(l.t_at_min, n, T(0));
  std::fill_n(l.code, n, Int<T>(kRunning));
  if constexpr (Relaxed || Secant) {
    std::fill_n(l.prev_t, n, T(0));
    std::fill_n(l.prev_f, n, T(0));
  }
  if constexpr (Relaxed) {
    std::fill_n(l.omega, n, T(s.relaxation));
    std::fill_n(l.prev_step, n, T(0));
  }
  if constexpr (Secant) std::fill_n(l.refining, n, Int<T>(0));
  const T scale = SphereTrace<T>(s, c, T(0), T(0)).scale();
  const T eps_at_0 = s.eps_mode == EpsMode::absolute ? T(s.hit_eps)
                     : s.eps_mode == EpsMode::pixel  ? T(c.footprint_at_0)
                                                     : T(0);
  const T eps_slope = s.eps_mode == EpsMode::relative ? T(s.hit_eps)
                      : s.eps_mode == EpsMode::pixel  ? T(c.footprint_slope)
                                                      : T(0);
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
    const int running =
        step == 1 ? feed_lanes<true, Relaxed, Secant>(l, count, step, scale, eps_at_0, eps_slope, s.max_steps)
                  : feed_lanes<false, Relaxed, Secant>(l, count, step, scale, eps_at_0, eps_slope, s.max_steps);
    if (running == 0 || running < count / 2) count = compact<Relaxed, Secant>(l, count, records);
  }
}

// Marches rays[ids[i]] into records[ids[i]], i < n <= kMaxPacket, where the lanes' step rule does not apply (the
// fixed marcher's steps and bisections): each ray's own Trace, fed from shared batches.
template <class Trace, class T>
void march_traces(const sdf::Tape& tape, const PacketRay<T>* rays, int* ids, int n, RayRecord<T>* records,
                  const MarchSettings& s, const MarchContext& c) {
  Trace traces[kMaxPacket];
  for (int i = 0; i < n; ++i) traces[ids[i]] = Trace(s, c, T(0), static_cast<T>(rays[ids[i]].max_dist));
  int count = n;  // max_steps > 0 (march_packet): every trace wants a first value
  while (count > 0) {
    int still = 0;  // compacts ids in place: still <= the index read
    for (int b = 0; b < count; b += sdf::kBatch) {
      const int k = std::min(sdf::kBatch, count - b);
      alignas(64) T x[sdf::kBatch], y[sdf::kBatch], z[sdf::kBatch], f[sdf::kBatch];
      for (int j = 0; j < k; ++j) {
        const PacketRay<T>& ray = rays[ids[b + j]];
        const glm::vec<3, T> p = ray.origin + ray.direction * traces[ids[b + j]].t();  // as march()
        x[j] = p.x;
        y[j] = p.y;
        z[j] = p.z;
      }
      sdf::evaluate_batch(tape, x, y, z, f, k);
      for (int j = 0; j < k; ++j) {
        const int i = ids[b + j];
        traces[i].feed(f[j]);
        if (traces[i].done()) {
          records[i] = traces[i].record();
        } else {
          ids[still++] = i;
        }
      }
    }
    count = still;
  }
}

}  // namespace

template <class T>
void march_packet(const sdf::Tape& tape, const PacketRay<T>* rays, RayRecord<T>* records, int n,
                  const MarchSettings& s, const MarchContext& c) {
  const auto one_point = [&tape](glm::vec<3, T> p) { return sdf::evaluate(tape, p); };
  int active[kMaxPacket];
  // settings_invalid reads max_dist only as max_dist > 0: decided once here rather than per ray.
  MarchSettings unit = s;
  unit.max_dist = 1;
  const bool settings_bad = settings_invalid(unit, c);
  for (int base = 0; base < n; base += kMaxPacket) {
    const int m = std::min(kMaxPacket, n - base);
    int count = 0;
    for (int i = 0; i < m; ++i) {
      const PacketRay<T>& ray = rays[base + i];
      // Rare: one point at a time (with no step allowed, march() ends the ray without evaluating).
      if (settings_bad || !(0 < s.max_steps) || !(ray.max_dist > 0) ||
          detail::ray_degenerate(ray.origin, ray.direction, T(0))) {
        MarchSettings own = s;
        own.max_dist = ray.max_dist;
        records[base + i] = march<T>(one_point, ray.origin, ray.direction, own, c);
      } else {
        active[count++] = i;
      }
    }
    const bool relaxed = s.marcher == Marcher::relaxed, secant = s.refine == sdf::HitRefine::secant;
    const auto run = [&](auto path) { path(tape, rays + base, active, count, records + base, s, c); };
    if (s.marcher == Marcher::fixed) run(march_traces<FixedTrace<T>, T>);
    else if (relaxed && secant) run(march_lanes<true, true, T>);
    else if (relaxed) run(march_lanes<true, false, T>);
    else if (secant) run(march_lanes<false, true, T>);
    else run(march_lanes<false, false, T>);
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
