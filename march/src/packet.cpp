#include "marchcheck/march/packet.hpp"

#include "marchcheck/sdf/vector_width.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>
#include <limits>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace marchcheck::march {

namespace {

constexpr int kMaxPacket = 256;  // rays in flight at once: one render tile

// A packet of rays as structure of arrays, so that the bookkeeping of a step, not only the evaluation, runs on
// whole vectors of lanes. Rays that end stay in place, masked, until half the packet has ended; then the packet is
// compacted (at a quarter, an eighth, or 16 lanes, lee-flat rendered 1-5% slower: compaction costs more than
// masked lanes).
// Integers as wide as T: a comparison of vectors of T gives lanes of this width, and a select needs them alike.
template <class T>
using Int = std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>;

// How the lanes step: SphereTrace's rule (sphere and scaled marchers), with over-relaxation (relaxed), or
// FixedTrace's steps and bisection (fixed).
enum class Rule { sphere, relaxed, fixed };

// A row of lanes: kMaxPacket of them and 64 bytes more, so that no two rows start at the same offset in a 4 KiB
// page (rows of 256 floats, 1 KiB, did every fourth row): a load whose address matches a pending store's in its
// low 12 bits can wait for that store, and the feeds store to the rows beside those they load.
template <class T>
constexpr int kRow = kMaxPacket + 64 / static_cast<int>(sizeof(T));

template <class T>
struct Lanes {
  alignas(64) T ox[kRow<T>], oy[kRow<T>], oz[kRow<T>], dx[kRow<T>], dy[kRow<T>], dz[kRow<T>];
  // last_f: the field where the lane ended (signed: a hit's secant root needs it).
  alignas(64) T t[kRow<T>], max_dist[kRow<T>], min_abs[kRow<T>], t_at_min[kRow<T>], last_f[kRow<T>];
  alignas(64) Int<T> steps[kRow<T>], code[kRow<T>], id[kRow<T>];
  // The last forward step's start and f (the relaxed marcher's fallback, the secant's other sample); the relaxed
  // marcher's factor (1 once it stepped back).
  alignas(64) T prev_t[kRow<T>], prev_f[kRow<T>], omega[kRow<T>];
  // Rule::fixed: the bracket being bisected (while stepping, lo is the last step's start), and whether it is.
  alignas(64) T lo[kRow<T>], hi[kRow<T>];
  alignas(64) Int<T> bisecting[kRow<T>];
  // The points the next evaluation is at (origin + direction t, set where t is: moved by compaction), and the
  // field's values there (scratch of one step, never compacted).
  alignas(64) T x[kRow<T>], y[kRow<T>], z[kRow<T>], f[kRow<T>];
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

// The feeds below run on whole vectors of lanes, written with GCC's vector extension (the target's widest vector:
// 16 floats on AVX-512) rather than left to the loop vectoriser: every select is a blend and every store a whole
// store. The vectoriser had turned the relaxed marcher's selects into branches around masked stores (its feed cost
// twice the sphere's per lane), and the fixed marcher's march took 1.7 times as long as it does now. A lane's
// arithmetic is the scalar marchers', one IEEE operation for one, so the lanes stay bit-identical to them.
using sdf::kVectorBytes;
template <class T>
struct Simd;
template <>
struct Simd<float> {
  typedef float V __attribute__((vector_size(kVectorBytes)));
  typedef std::int32_t I __attribute__((vector_size(kVectorBytes)));  // a comparison's lanes: -1 true, 0 false
};
template <>
struct Simd<double> {
  typedef double V __attribute__((vector_size(kVectorBytes)));
  typedef std::int64_t I __attribute__((vector_size(kVectorBytes)));
};
template <class T>
constexpr int kWidth = kVectorBytes / static_cast<int>(sizeof(T));  // lanes per vector; kMaxPacket is a multiple

static_assert(kMaxPacket % kWidth<double> == 0 && kMaxPacket % kWidth<float> == 0);

template <class A, class E>
A load(const E* at) {
  static_assert(sizeof(A) == kVectorBytes && sizeof(std::declval<A&>()[0]) == sizeof(E));  // one vector of E
  A a;
  std::memcpy(&a, at, sizeof a);
  return a;
}
template <class A, class E>
void store(E* at, A a) {
  static_assert(sizeof(A) == kVectorBytes && sizeof(std::declval<A&>()[0]) == sizeof(E));  // one vector of E
  std::memcpy(at, &a, sizeof a);
}
// |v| as std::abs: the sign bit cleared (-0 gives +0, NaN stays NaN).
template <class T>
typename Simd<T>::V abs_lanes(typename Simd<T>::V v) {
  using I = typename Simd<T>::I;
  const I magnitude = I{} + std::numeric_limits<Int<T>>::max();
  return reinterpret_cast<typename Simd<T>::V>(reinterpret_cast<I>(v) & magnitude);
}

// One bit per lane of a comparison's result, lane k in bit k: the mask itself where the target has mask registers,
// else the lanes' sign bits (a movemask: read lane by lane, lee-flat's render took 15% longer on AVX2).
template <class I>
unsigned lane_mask(I m) {
  constexpr int kLanes = static_cast<int>(sizeof(I) / sizeof(m[0]));
#if defined(__AVX512F__)
  const __m512i bits = reinterpret_cast<__m512i>(m);
  if constexpr (kLanes == 16) return _mm512_test_epi32_mask(bits, bits);
  else return _mm512_test_epi64_mask(bits, bits);
#elif defined(__AVX__)
  const __m256i bits = reinterpret_cast<__m256i>(m);
  if constexpr (kLanes == 8) return _mm256_movemask_ps(_mm256_castsi256_ps(bits));
  else return _mm256_movemask_pd(_mm256_castsi256_pd(bits));
#elif defined(__SSE2__)
  const __m128i bits = reinterpret_cast<__m128i>(m);
  if constexpr (kLanes == 4) return _mm_movemask_ps(_mm_castsi128_ps(bits));
  else return _mm_movemask_pd(_mm_castsi128_pd(bits));
#else
  unsigned out = 0;
  for (int k = 0; k < kLanes; ++k) out |= unsigned{m[k] != 0} << k;
  return out;
#endif
}

// How many lanes of a comparison's result are set.
template <class T>
int lanes_set(typename Simd<T>::I m) {
  return __builtin_popcount(lane_mask(m));
}

// The part of a step every rule shares, detail::Tracker::saw and end, for the kWidth lanes from i: they saw v at t
// and want `code` (already kRunning, or how they end). A lane that had ended keeps its code; its code, steps and
// last f change only when it ends (so compaction need not move them for running lanes). Returns which lanes were
// running. Always inlined: built for AVX2, GCC kept it a call, its vectors passed through memory (lee-flat's render
// took 3% longer).
template <class T>
[[gnu::always_inline]] inline typename Simd<T>::I settle(Lanes<T>& l, int i, typename Simd<T>::I& code,
                                                         typename Simd<T>::V v, typename Simd<T>::V t,
                                                         typename Simd<T>::V a, Int<T> step) {
  using V = typename Simd<T>::V;
  using I = typename Simd<T>::I;
  const I old = load<I>(l.code + i);
  const V old_min = load<V>(l.min_abs + i), old_t_at_min = load<V>(l.t_at_min + i);
  const I live = old == kRunning;
  const I better = live & (a < old_min);
  code = live ? code : old;
  const I ends = code != old;
  store(l.t_at_min + i, better ? t : old_t_at_min);
  store(l.min_abs + i, better ? a : old_min);
  // Few steps end a lane: the three stores only at those (the feeds are bound by their stores).
  if (lanes_set<T>(ends) != 0) {
    const I old_steps = load<I>(l.steps + i);
    store(l.steps + i, ends ? I{} + step : old_steps);
    store(l.last_f + i, ends ? v : load<V>(l.last_f + i));
    store(l.code + i, code);
  }
  return live;
}

// Sets the kWidth lanes from i at t: t and the point there, origin + direction t as march() computes it.
template <class T>
void move_to(Lanes<T>& l, int i, typename Simd<T>::V t) {
  using V = typename Simd<T>::V;
  store(l.t + i, t);
  store(l.x + i, load<V>(l.ox + i) + load<V>(l.dx + i) * t);
  store(l.y + i, load<V>(l.oy + i) + load<V>(l.dy + i) * t);
  store(l.z + i, load<V>(l.oz + i) + load<V>(l.dz + i) * t);
}

// The outcomes as lanes, for a feed at step `step`: out_of_steps is miss_steps at the last step, else running.
template <class T>
struct LaneCodes {
  using I = typename Simd<T>::I;
  I miss_far = I{} + Int<T>(Outcome::miss_far), hit = I{} + Int<T>(Outcome::hit),
    inside = I{} + Int<T>(Outcome::inside), invalid = I{} + Int<T>(Outcome::invalid), out_of_steps;
  LaneCodes(int step, int max_steps)
      : out_of_steps(I{} + (step >= max_steps ? Int<T>(Outcome::miss_steps) : Int<T>(kRunning))) {}
};

// The lane numbers 0 to kWidth - 1.
template <class T>
typename Simd<T>::I lane_numbers() {
  typename Simd<T>::I lane{};
  for (int k = 0; k < kWidth<T>; ++k) lane[k] = k;
  return lane;
}

// Which of the lanes from lane i have `count` past them: the passes run over the lanes from 0 to count rounded up to
// whole vectors, and those past count are stale copies or padding, computed and stored like the rest but never read
// into a record.
template <class T>
typename Simd<T>::I in_packet(int i, int count) {
  return lane_numbers<T>() < count - i;
}

// Which of the lanes from lane i, with codes `code`, are still running.
template <class T>
typename Simd<T>::I running_lanes(typename Simd<T>::I code, int i, int count) {
  return (code == kRunning) & in_packet<T>(i, count);
}

// SphereTrace::feed for every lane at once (Relaxed: with its over-relaxation and step back, else omega = 1;
// Secant: keeping the samples a hit's secant root is taken from); the same expressions in the same order. All
// lanes of a packet start together, so a running lane's step count is the packet's: `step` (this evaluation's
// number). Every lane computes every outcome, then selects. Returns the number of lanes still running.
// Perturbed: the rule has a perturbation's width; without one (+inf), its step and radii are the plain terms, bit
// for bit, and the lanes skip the perturbed terms (the relaxed marcher takes four steps' worth a lane: half its
// arithmetic).
template <bool First, bool Relaxed, bool Secant, bool Perturbed, class T>
int feed_lanes(Lanes<T>& l, int count, int step, const StepRule<T> rule, T eps_at_0, T eps_slope, int max_steps) {
  using V = typename Simd<T>::V;
  using I = typename Simd<T>::I;
  const auto step_of = [&rule](V v, V omega) {
    if constexpr (Perturbed) return rule.template step<V>(v, omega);
    else return rule.template plain_step<V>(v, omega);
  };
  const auto radii = [&rule](V a, V b) {
    if constexpr (Perturbed) return rule.template radii<V>(a, b);
    else return rule.template plain_radii<V>(a, b);
  };
  const V one = V{} + T(1);
  const T largest = std::numeric_limits<T>::max();
  const LaneCodes<T> c(step, max_steps);
  int still = 0;  // the lanes still running
  for (int i = 0; i < count; i += kWidth<T>) {
    const V v = load<V>(l.f + i), t = load<V>(l.t + i), a = abs_lanes<T>(v);
    const V eps = eps_at_0 + eps_slope * t;  // hit_threshold: each mode is a + b t with an exact zero term
    // As SphereTrace: past max_dist where a plain step passes it too (an over-relaxed one may yet step back).
    const V plain_reach = t + step_of(v, one);
    I back{};
    V next = plain_reach;
    V prev_t{}, prev_f{}, omega = one;
    if constexpr (Relaxed || Secant) {
      prev_t = load<V>(l.prev_t + i);
      prev_f = load<V>(l.prev_f + i);
    }
    if constexpr (Relaxed) {
      // Where the two unbounding spheres do not overlap, back to the last forward step's start, then omega 1.
      // The last step's length, SphereTrace's prev_step, is rule.step(prev_f, omega) bit for bit: a forward step
      // is rule.step(v, omega) with omega unchanged, a step back rule.step(prev_f, 1) with omega 1 from then on.
      omega = load<V>(l.omega + i);
      const V reach = radii(a, prev_f), prev_step = step_of(prev_f, omega), back_to = prev_t + step_of(prev_f, one);
      back = (omega > one) & (reach < prev_step);
      const V ahead = t + step_of(v, omega);
      next = back ? back_to : ahead;
    }
    const V md = load<V>(l.max_dist + i);
    I code = c.out_of_steps;
    code = next > md ? c.miss_far : code;
    code = plain_reach > md ? code : c.out_of_steps;
    code = back ? c.out_of_steps : code;
    const I moved = code;  // t moves on unless the step below ends the ray where it is
    code = (~back & (v < eps)) ? c.hit : code;
    if constexpr (First) code = v < -eps ? c.inside : code;
    code = a <= largest ? code : c.invalid;  // not finite
    const I live = settle(l, i, code, v, t, a, Int<T>(step));
    const I forward = live & (code == moved);  // t moves on: the step taken (or the step back)
    move_to(l, i, forward ? next : t);
    if constexpr (Relaxed || Secant) {
      const I stepped = forward & ~back;  // a forward step: the next one's fallback
      if constexpr (Relaxed) store(l.omega + i, back ? one : omega);
      store(l.prev_t + i, stepped ? t : prev_t);
      store(l.prev_f + i, stepped ? v : prev_f);
    }
    still += lanes_set<T>(running_lanes<T>(code, i, count));
  }
  return still;
}

// FixedTrace::feed for every lane at once: steps of fixed_step; a step that lands inside (f below -threshold)
// bisects the bracket from the previous point until |f| is below the threshold at its midpoint or the bracket
// cannot shrink. The same expressions as FixedTrace. While stepping, lo is FixedTrace's prev_t, so that a step
// that lands inside updates the bracket as a bisection does (v < -threshold <= 0: t becomes hi) and one rule
// serves both.
template <bool First, class T>
int feed_fixed_lanes(Lanes<T>& l, int count, int step, T fixed_step, T eps_at_0, T eps_slope, int max_steps) {
  using V = typename Simd<T>::V;
  using I = typename Simd<T>::I;
  const T largest = std::numeric_limits<T>::max();
  const LaneCodes<T> c(step, max_steps);
  const I at_last_step = I{} - Int<T>(step >= max_steps), first = I{} - Int<T>(First);
  int still = 0;  // the lanes still running
  for (int i = 0; i < count; i += kWidth<T>) {
    const V v = load<V>(l.f + i), t = load<V>(l.t + i), a = abs_lanes<T>(v), lo = load<V>(l.lo + i),
            hi = load<V>(l.hi + i);
    const V eps = eps_at_0 + eps_slope * t;  // hit_threshold at the point evaluated, a step's or a midpoint
    const I bisecting = load<I>(l.bisecting + i) != 0, finite = a <= largest;
    // Bisecting: t is the bracket's midpoint; it ends there, or the side of the same sign as v moves to it.
    const I bisect_hit = (a < eps) | ~((t > lo) & (t < hi));
    // Stepping: below the threshold is a hit, unless the step went past the surface (below -threshold after the
    // first step): then bisect [lo, t].
    const I below = v < eps, step_hit = below & ((v > -eps) | first), inside_first = first & (v < -eps);
    const I ends_here = (bisecting & bisect_hit) | (~bisecting & step_hit);
    const I splits = (bisecting & ~bisect_hit) | (~bisecting & below & ~step_hit);
    const I forward = ~bisecting & ~below, above = v > T(0);
    const V lo_next = (above | forward) ? t : lo, hi_next = above ? hi : t;
    const V mid = lo_next + (hi_next - lo_next) * T(0.5), ahead = t + fixed_step;
    I code = (~splits & (ahead > load<V>(l.max_dist + i))) ? c.miss_far : c.out_of_steps;
    code = ends_here ? c.hit : code;
    code = inside_first ? c.inside : code;
    code = finite ? code : c.invalid;
    V t_next = splits ? mid : ahead;  // where the field is wanted next, or where the ray ends
    t_next = (splits & at_last_step) ? lo_next : t_next;
    t_next = (ends_here | inside_first | ~finite) ? t : t_next;
    const I live = settle(l, i, code, v, t, a, Int<T>(step));
    move_to(l, i, live ? t_next : t);
    // A lane that ended never reads these again.
    store(l.lo + i, lo_next);
    store(l.hi + i, hi_next);
    store(l.bisecting + i, splits);
    still += lanes_set<T>(running_lanes<T>(code, i, count));
  }
  return still;
}

#if defined(__AVX2__) && !defined(__AVX512F__)
// AVX2's compress, for `packed`: for each mask of a vector's kLanes lanes, the 32-bit words that the kept lanes
// take, in order, as eight 4-bit word numbers (word w in bits 4w to 4w + 3).
template <int kLanes>
constexpr std::array<std::uint32_t, (1 << kLanes)> kept_words() {
  constexpr int kWords = 8 / kLanes;  // 32-bit words a lane
  std::array<std::uint32_t, (1 << kLanes)> table{};
  for (int mask = 0; mask < (1 << kLanes); ++mask) {
    int w = 0;
    for (int lane = 0; lane < kLanes; ++lane)
      if (mask >> lane & 1)
        for (int word = 0; word < kWords; ++word, ++w) table[mask] |= std::uint32_t(lane * kWords + word) << (4 * w);
  }
  return table;
}
#endif

// The lanes of `v` where `keep` is set, packed to the front in order; the rest zero. AVX-512 has it as one
// instruction (a compress from register to register), AVX2 as a permutation from a table of the masks (lane by
// lane, it made lee-flat's render 9% slower on AVX2); elsewhere lane by lane.
template <class I>
I packed(I v, I keep) {
  constexpr int kLanes = static_cast<int>(sizeof(I) / sizeof(v[0]));
#if defined(__AVX512F__)
  if constexpr (sizeof(I) == 64) {
    const __m512i bits = reinterpret_cast<__m512i>(v);
    if constexpr (kLanes == 16)
      return reinterpret_cast<I>(_mm512_maskz_compress_epi32(static_cast<__mmask16>(lane_mask(keep)), bits));
    else
      return reinterpret_cast<I>(_mm512_maskz_compress_epi64(static_cast<__mmask8>(lane_mask(keep)), bits));
  }
#elif defined(__AVX2__)
  if constexpr (sizeof(I) == 32) {
    static constexpr auto kTable = kept_words<kLanes>();
    const unsigned mask = lane_mask(keep);
    const __m256i word = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i order = _mm256_and_si256(
        _mm256_srlv_epi32(_mm256_set1_epi32(static_cast<int>(kTable[mask])), _mm256_slli_epi32(word, 2)),
        _mm256_set1_epi32(7));
    const __m256i moved = _mm256_permutevar8x32_epi32(reinterpret_cast<__m256i>(v), order);
    const int words_kept = __builtin_popcount(mask) * (8 / kLanes);
    return reinterpret_cast<I>(_mm256_and_si256(moved, _mm256_cmpgt_epi32(_mm256_set1_epi32(words_kept), word)));
  }
#endif
  I out{};
  for (int k = 0, j = 0; k < kLanes; ++k)
    if (keep[k]) out[j++] = v[k];
  return out;
}

// Writes the records of the lanes that ended (Secant: a hit with a step left and a secant root apart from where it
// stopped joins `roots`) and packs the running ones to the front; returns their count.
// A vector of lanes at a time (packed): the ended lanes' numbers into a list, then every row the lanes keep, as
// their bits. Lane by lane, as loops over index lists, compaction had been a third of the relaxed marcher's
// bookkeeping: it is a cost per ray, which the relaxed marcher's fewer evaluations do not share.
template <Rule R, bool Secant, class T>
int compact(Lanes<T>& l, int count, RayRecord<T>* records, int max_steps, SecantRoots<T>& roots) {
  using I = typename Simd<T>::I;
  const auto running = [&](int i) { return running_lanes<T>(load<I>(l.code + i), i, count); };
  // Each vector is stored whole, from where the list (or the packed rows below) has got to, at most lane i: the
  // lanes past the end are overwritten next, or never read.
  alignas(64) Int<T> ended[kMaxPacket];
  int done = 0;
  for (int i = 0; i < count; i += kWidth<T>) {
    const I ends = ~running(i) & in_packet<T>(i, count);
    store(ended + done, packed(lane_numbers<T>() + i, ends));
    done += lanes_set<T>(ends);
  }
  for (int e = 0; e < done; ++e) {
    const auto i = ended[e];
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
  // The rows moved: a running lane's steps and last f are not kept yet (settle), and its code is kRunning (set below).
  const auto moved_rows = [&](auto&& move) {
    for (T* a : {l.ox, l.oy, l.oz, l.dx, l.dy, l.dz, l.t, l.x, l.y, l.z, l.max_dist, l.min_abs, l.t_at_min}) move(a);
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
  };
  int kept = 0;
  for (int i = 0; i < count; i += kWidth<T>) {
    const I keep = running(i);
    const int n = lanes_set<T>(keep);
    // In place: the vector is read before any lane past it is written (kept <= i). Where every lane of it runs and
    // none before it ended, it stays.
    if (kept != i || n != std::min(kWidth<T>, count - i))
      moved_rows([&](auto* row) { store(row + kept, packed(load<I>(row + i), keep)); });
    kept += n;
  }
  std::fill_n(l.code, kept, Int<T>(kRunning));
  return kept;
}

// A ray the lanes do not take, one point at a time: march() ends it without a step (no step allowed, clipped away,
// or not a ray it can march).
template <class T>
RayRecord<T> march_alone(const sdf::Tape& tape, const PacketRay<T>& ray, const MarchSettings& s,
                         const MarchContext& c) {
  MarchSettings own = s;
  own.max_dist = ray.max_dist;
  return march<T>([&tape](glm::vec<3, T> p) { return sdf::evaluate(tape, p); }, ray.origin, ray.direction, own, c);
}

// detail::ray_degenerate (not finite, or no direction) for the n lanes filled, a vector at a time over their
// components (detail::marchable_components on vectors). Such rays are rare; they leave the packet for
// march_alone. (Tested per ray before the lanes were filled, as a chain of twenty scalar compares, it cost 4% of
// lee-flat's render and 5% of crum-torus's.) Returns the number of lanes left.
template <class T>
int drop_degenerate(const sdf::Tape& tape, Lanes<T>& l, int n, const PacketRay<T>* rays, RayRecord<T>* records,
                    const MarchSettings& s, const MarchContext& c) {
  using V = typename Simd<T>::V;
  using I = typename Simd<T>::I;
  alignas(64) Int<T> degenerate[kMaxPacket];
  I found{};
  for (int i = 0; i < n; i += kWidth<T>) {
    const I marchable = detail::marchable_components<T, V>(load<V>(l.ox + i), load<V>(l.oy + i), load<V>(l.oz + i),
                                                           load<V>(l.dx + i), load<V>(l.dy + i), load<V>(l.dz + i));
    const I bad = ~marchable & in_packet<T>(i, n);  // padding is not
    store(degenerate + i, bad);
    found |= bad;
  }
  if (lanes_set<T>(found) == 0) return n;
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    if (degenerate[i] != 0) {
      records[l.id[i]] = march_alone(tape, rays[l.id[i]], s, c);
      continue;
    }
    for (T* a : {l.ox, l.oy, l.oz, l.dx, l.dy, l.dz, l.t, l.prev_t, l.lo, l.max_dist}) a[kept] = a[i];
    l.id[kept++] = l.id[i];
  }
  return kept;
}

// Marches rays[ids[i]] over spans[i] (clip_span's) into records[ids[i]], i < n <= kMaxPacket, by rule R; the
// degenerate ones one at a time (drop_degenerate). Without ids (nullptr), rays[i] over all of it, [0, max_dist]:
// the usual case, whose lanes fill from consecutive rays (a fill through ids and spans made lee-flat's march 11%
// slower).
template <Rule R, bool Secant, class T>
void march_lanes(const sdf::Tape& tape, const PacketRay<T>* rays, const int* ids, const Span<T>* spans, int n,
                 RayRecord<T>* records, const MarchSettings& s, const MarchContext& c) {
  Lanes<T> l;
  SecantRoots<T> roots;
  // The feeds read whole vectors: the last one's lanes past n are set too, their results never read.
  const int padded = (n + kWidth<T> - 1) / kWidth<T> * kWidth<T>;
  std::fill_n(l.min_abs, padded, std::numeric_limits<T>::infinity());
  std::fill_n(l.last_f, padded, std::numeric_limits<T>::infinity());
  std::fill_n(l.t_at_min, padded, T(0));
  std::fill_n(l.code, padded, Int<T>(kRunning));
  std::fill_n(l.steps, padded, Int<T>(0));  // read (and kept) by settle before a lane ends
  for (T* a : {l.prev_f, l.hi}) std::fill_n(a, padded, T(0));
  std::fill_n(l.omega, padded, T(s.relaxation));
  std::fill_n(l.bisecting, padded, Int<T>(0));
  // The field's values too: lanes past the count that drop_degenerate leaves are read by the first feed.
  std::fill_n(l.f, padded, T(0));
  for (T* a : {l.ox, l.oy, l.oz, l.dx, l.dy, l.dz, l.t, l.prev_t, l.lo, l.max_dist}) std::fill(a + n, a + padded, T(0));
  const auto fill = [&l](int i, const PacketRay<T>& ray, int id, Span<T> span) {
    l.ox[i] = ray.origin.x;
    l.oy[i] = ray.origin.y;
    l.oz[i] = ray.origin.z;
    l.dx[i] = ray.direction.x;
    l.dy[i] = ray.direction.y;
    l.dz[i] = ray.direction.z;
    // As march(): from the start of the ray's span (the traces' t and their last step's start), to its end.
    l.t[i] = l.prev_t[i] = l.lo[i] = span.t0;
    l.max_dist[i] = span.t1;
    l.id[i] = id;
  };
  if (ids) {
    for (int i = 0; i < n; ++i) fill(i, rays[ids[i]], ids[i], spans[i]);
  } else {
    for (int i = 0; i < n; ++i) fill(i, rays[i], i, {T(0), static_cast<T>(rays[i].max_dist)});
  }
  n = drop_degenerate(tape, l, n, rays, records, s, c);
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
  for (int i = 0; i < n; i += kWidth<T>) move_to(l, i, load<typename Simd<T>::V>(l.t + i));
  int count = n;
  for (int step = 1; count > 0; ++step) {
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
  int active[kMaxPacket];
  Span<T> spans[kMaxPacket];
  // settings_invalid reads max_dist only as max_dist > 0: decided once here rather than per ray.
  MarchSettings unit = s;
  unit.max_dist = 1;
  const bool settings_bad = settings_invalid(unit, c) || !(0 < s.max_steps);
  const bool clipped = s.clip != sdf::Clip::none;
  for (int base = 0; base < n; base += kMaxPacket) {
    const int m = std::min(kMaxPacket, n - base);
    // The usual case: every ray marched over all of its length, the lanes filled from consecutive rays (march_lanes
    // without ids).
    int reaching = 0;
    for (int i = 0; i < m; ++i) reaching += rays[base + i].max_dist > 0;
    const bool whole = !settings_bad && !clipped && reaching == m;
    int count = whole ? m : 0;
    if (!whole) {  // each ray sorted: marched alone, or in the lanes over its span
      for (int i = 0; i < m; ++i) {
        const PacketRay<T>& ray = rays[base + i];
        // Rare: one point at a time (with no step allowed, or outside the clip box, march() ends the ray without
        // evaluating). Each ray's span is found once, here (unclipped: all of it, as clip_span gives it).
        // Degenerate rays too, which the lanes find (drop_degenerate) unless the ray is clipped first.
        bool marchable = (!settings_bad) & (ray.max_dist > 0);
        Span<T> span{T(0), static_cast<T>(ray.max_dist)};
        if (marchable && clipped) {
          marchable = !detail::ray_degenerate(ray.origin, ray.direction, T(0));
          if (marchable) span = clip_span(s, c, ray.origin, ray.direction, T(0), static_cast<T>(ray.max_dist));
        }
        if (!marchable || span.empty()) {
          records[base + i] = march_alone(tape, ray, s, c);
        } else {
          active[count] = i;
          spans[count++] = span;
        }
      }
    }
    const bool relaxed = s.marcher == Marcher::relaxed, secant = s.refine == sdf::HitRefine::secant;
    const int* ids = whole ? nullptr : active;
    const auto run = [&](auto path) { path(tape, rays + base, ids, spans, count, records + base, s, c); };
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
