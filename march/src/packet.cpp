#include "marchcheck/march/packet.hpp"

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <limits>

namespace marchcheck::march {

namespace {

constexpr int kMaxPacket = 256;  // rays in flight at once: one render tile

// The state of a packet of sphere-traced rays (sphere and scaled marchers: no relaxation) as structure of
// arrays, so that the bookkeeping of a step, not only the evaluation, runs as vectorised loops. Rays that end
// stay in place, masked, until a quarter of the packet has ended; then the packet is compacted.
// Integers as wide as T, so a loop mixing them with T vectorises.
template <class T>
using Int = std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>;

template <class T>
struct Lanes {
  alignas(64) T ox[kMaxPacket], oy[kMaxPacket], oz[kMaxPacket], dx[kMaxPacket], dy[kMaxPacket], dz[kMaxPacket];
  alignas(64) T t[kMaxPacket], max_dist[kMaxPacket], min_abs[kMaxPacket], t_at_min[kMaxPacket], last_abs[kMaxPacket];
  alignas(64) T x[kMaxPacket], y[kMaxPacket], z[kMaxPacket], f[kMaxPacket];
  alignas(64) Int<T> steps[kMaxPacket], code[kMaxPacket], id[kMaxPacket];
};

constexpr int kRunning = -1;  // else the Outcome

// SphereTrace::feed for every lane at once, for omega = 1; the same expressions in the same order.
template <class T>
void feed_lanes(Lanes<T>& l, int count, T scale, T eps_at_0, T eps_slope, int max_steps) {
  using I = Int<T>;
  const T largest = std::numeric_limits<T>::max();
  const I running = kRunning, miss_steps = I(Outcome::miss_steps), miss_far = I(Outcome::miss_far),
          hit = I(Outcome::hit), inside = I(Outcome::inside), invalid = I(Outcome::invalid), limit = max_steps;
  for (int i = 0; i < count; ++i) {
    const T v = l.f[i], t = l.t[i], a = std::abs(v);
    const I steps = l.steps[i] + 1;
    const T eps = eps_at_0 + eps_slope * t;  // hit_threshold: each mode is a + b t with an exact zero term
    const T next = t + v * scale;
    I code = steps >= limit ? miss_steps : running;
    code = next > l.max_dist[i] ? miss_far : code;
    const I moved = code;  // t moves on unless the step below ends the ray where it is
    code = v < eps ? hit : code;
    code = steps == 1 && v < -eps ? inside : code;
    code = a <= largest ? code : invalid;  // not finite
    const bool live = l.code[i] == running;
    const bool better = live && a < l.min_abs[i];
    l.steps[i] = live ? steps : l.steps[i];
    l.last_abs[i] = live ? a : l.last_abs[i];
    l.t_at_min[i] = better ? t : l.t_at_min[i];
    l.min_abs[i] = better ? a : l.min_abs[i];
    l.t[i] = live && code == moved ? next : t;
    l.code[i] = live ? code : l.code[i];
  }
}

// Writes the records of the lanes that ended and packs the running ones to the front; returns their count.
template <class T>
int compact(Lanes<T>& l, int count, RayRecord<T>* records) {
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    if (l.code[i] != kRunning) {
      RayRecord<T>& r = records[l.id[i]];
      r.outcome = static_cast<Outcome>(l.code[i]);
      r.t = l.t[i];
      r.steps = r.evals = static_cast<int>(l.steps[i]);
      r.min_abs_f = l.min_abs[i];
      r.t_at_min = l.t_at_min[i];
      r.last_abs_f = l.last_abs[i];
      continue;
    }
    if (kept != i) {
      for (T* a : {l.ox, l.oy, l.oz, l.dx, l.dy, l.dz, l.t, l.max_dist, l.min_abs, l.t_at_min, l.last_abs}) a[kept] = a[i];
      for (Int<T>* a : {l.steps, l.code, l.id}) a[kept] = a[i];
    }
    ++kept;
  }
  return kept;
}

// Marches rays[ids[i]] into records[ids[i]], i < n <= kMaxPacket, for the sphere and scaled marchers.
template <class T>
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
    l.t[i] = 0;
    l.max_dist[i] = static_cast<T>(ray.max_dist);
    l.min_abs[i] = l.last_abs[i] = std::numeric_limits<T>::infinity();
    l.t_at_min[i] = 0;
    l.steps[i] = 0;
    l.code[i] = kRunning;
    l.id[i] = ids[i];
  }
  const T scale = SphereTrace<T>(s, c, T(0), T(0)).scale();
  const T eps_at_0 = s.eps_mode == EpsMode::absolute ? T(s.hit_eps)
                     : s.eps_mode == EpsMode::pixel  ? T(c.footprint_at_0)
                                                     : T(0);
  const T eps_slope = s.eps_mode == EpsMode::relative ? T(s.hit_eps)
                      : s.eps_mode == EpsMode::pixel  ? T(c.footprint_slope)
                                                      : T(0);
  int count = n;
  while (count > 0) {
    for (int i = 0; i < count; ++i) {
      // As march(): origin + direction * t.
      l.x[i] = l.ox[i] + l.dx[i] * l.t[i];
      l.y[i] = l.oy[i] + l.dy[i] * l.t[i];
      l.z[i] = l.oz[i] + l.dz[i] * l.t[i];
    }
    for (int b = 0; b < count; b += sdf::kBatch)
      sdf::evaluate_batch(tape, l.x + b, l.y + b, l.z + b, l.f + b, std::min(sdf::kBatch, count - b));
    feed_lanes(l, count, scale, eps_at_0, eps_slope, s.max_steps);
    int running = 0;
    for (int i = 0; i < count; ++i) running += l.code[i] == kRunning;
    if (running == 0 || running < count - count / 4) count = compact(l, count, records);
  }
}

}  // namespace

template <class T>
void march_packet(const sdf::Tape& tape, const PacketRay<T>* rays, RayRecord<T>* records, int n,
                  const MarchSettings& s, const MarchContext& c) {
  const auto one_point = [&tape](glm::vec<3, T> p) { return sdf::evaluate(tape, p); };
  SphereTrace<T> traces[kMaxPacket];
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
      if (s.marcher == Marcher::fixed || settings_bad || !(ray.max_dist > 0) ||
          detail::ray_degenerate(ray.origin, ray.direction, T(0))) {
        MarchSettings own = s;
        own.max_dist = ray.max_dist;
        records[base + i] = march<T>(one_point, ray.origin, ray.direction, own, c);  // rare: one point at a time
        continue;
      }
      traces[i] = SphereTrace<T>(s, c, T(0), static_cast<T>(ray.max_dist));
      if (traces[i].done()) {
        records[base + i] = traces[i].record();
      } else {
        active[count++] = i;
      }
    }
    if (s.marcher != Marcher::relaxed) {
      march_lanes(tape, rays + base, active, count, records + base, s, c);
      continue;
    }
    // Relaxed: each ray's own SphereTrace, fed from shared batches.
    while (count > 0) {
      int still = 0;  // compacts active in place: still <= the index read
      for (int b = 0; b < count; b += sdf::kBatch) {
        const int k = std::min(sdf::kBatch, count - b);
        alignas(64) T x[sdf::kBatch], y[sdf::kBatch], z[sdf::kBatch], f[sdf::kBatch];
        for (int j = 0; j < k; ++j) {
          const PacketRay<T>& ray = rays[base + active[b + j]];
          const T t = traces[active[b + j]].t();
          // As march(): origin + direction * t.
          const glm::vec<3, T> p = ray.origin + ray.direction * t;
          x[j] = p.x;
          y[j] = p.y;
          z[j] = p.z;
        }
        sdf::evaluate_batch(tape, x, y, z, f, k);
        for (int j = 0; j < k; ++j) {
          const int i = active[b + j];
          traces[i].feed(f[j]);
          if (traces[i].done()) {
            records[base + i] = traces[i].record();
          } else {
            active[still++] = i;
          }
        }
      }
      count = still;
    }
  }
}

template <class T>
void central_normals_packet(const sdf::Tape& tape, const glm::vec<3, T>* points, const T* eps,
                            NormalResult<T>* normals, int n) {
  using V = glm::vec<3, T>;
  // A batch holds the six probes of kBatch / 6 points.
  constexpr int kPoints = sdf::kBatch / 6;
  for (int base = 0; base < n; base += kPoints) {
    const int m = std::min(kPoints, n - base);
    alignas(64) T x[sdf::kBatch], y[sdf::kBatch], z[sdf::kBatch], f[sdf::kBatch];
    for (int i = 0; i < m; ++i) {
      const V p = points[base + i];
      const T e = eps[base + i];
      // The probes of estimate_normal, in its order: +x, -x, +y, -y, +z, -z.
      const V probes[6] = {p + V(e, 0, 0), p - V(e, 0, 0), p + V(0, e, 0), p - V(0, e, 0), p + V(0, 0, e), p - V(0, 0, e)};
      for (int j = 0; j < 6; ++j) {
        x[6 * i + j] = probes[j].x;
        y[6 * i + j] = probes[j].y;
        z[6 * i + j] = probes[j].z;
      }
    }
    sdf::evaluate_batch(tape, x, y, z, f, 6 * m);
    for (int i = 0; i < m; ++i) {
      const T* g = f + 6 * i;
      normals[base + i] = {detail::unit_or_zero(V(g[0] - g[1], g[2] - g[3], g[4] - g[5])), 6};
    }
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
