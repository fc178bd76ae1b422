#include "marchcheck/validation/stability.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/camera_relative.hpp"
#include "marchcheck/march/effects.hpp"
#include "marchcheck/march/normals.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/lipschitz.hpp"
#include "marchcheck/validation/convergence.hpp"
#include "marchcheck/validation/mesh_reference.hpp"
#include "marchcheck/validation/reference.hpp"
#include "marchcheck/validation/statistics.hpp"

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace marchcheck::validation {

namespace {

using glm::dvec3;
using glm::vec3;
using march::MarchSettings;
using march::Outcome;
using march::TapeField;

constexpr double kPi = std::numbers::pi;
constexpr float kFloatEps = std::numeric_limits<float>::epsilon();

// What a case fills in: its numbers, the clauses of its criterion it checked, and the first reason one failed.
struct Run {
  std::map<std::string, double>& m;
  const std::string& variant;  // the broken variant to run, "" for the marchers as they are
  std::vector<std::string> clauses, failed;
  std::string why;
  bool as(std::string_view v) const { return variant == v; }
  bool naive() const { return as("naive"); }
  // One clause of the criterion: each has a variant of its own that fails it alone.
  void require(const std::string& clause, bool condition, const std::string& reason) {
    if (std::find(clauses.begin(), clauses.end(), clause) == clauses.end()) clauses.push_back(clause);
    check(clause, condition, reason);
  }
  // What the case needs in order to test anything at all (not a clause: no variant of its own).
  void needs(const std::string& what, bool condition, const std::string& reason) { check("needs." + what, condition, reason); }
  bool ok() const { return failed.empty(); }

 private:
  void check(const std::string& id, bool condition, const std::string& reason) {
    if (condition || std::find(failed.begin(), failed.end(), id) != failed.end()) return;
    if (failed.empty()) why = reason;
    failed.push_back(id);
  }
};

struct Entry {
  std::string name, checks, criterion;
  std::vector<StabilityVariant> variants;  // the naive one first
  std::function<void(Run&, const StabilityOptions&)> run;
};

std::string num(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

std::string decade(double v) {
  return "1e" + std::to_string(static_cast<int>(std::lround(std::log10(v))));
}

double angle_deg(dvec3 a, dvec3 b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180 / kPi;
}

// The loop most shader code writes: no input guard, no finite check, no inside outcome, and a loop that ran
// out of steps read as a hit (its t is below max_dist). The naive variant of the degenerate-input cases.
template <class T, class F>
march::RayRecord<T> naive_march(const F& f, glm::vec<3, T> o, glm::vec<3, T> d, const MarchSettings& s) {
  march::RayRecord<T> r;
  T t = 0;
  for (int i = 0; i < s.max_steps; ++i) {
    const T v = f(o + d * t);
    ++r.steps;
    ++r.evals;
    if (v < T(s.hit_eps)) break;
    t += v;
    if (t > T(s.max_dist)) {
      r.outcome = Outcome::miss_far;
      r.t = t;
      return r;
    }
  }
  r.outcome = Outcome::hit;
  r.t = t;
  return r;
}

// ---- grazing rays and shallow incidence: steps against the closed-form laws ----

void grazing(Run& r, double b) {
  const double law = kPi * std::sqrt(2 / b);
  MarchSettings s = grazing_settings(b, r.naive() ? static_cast<int>(law / 2) : 1 << 24);
  if (r.as("eps_2b")) s.hit_eps = 2 * b;
  if (r.as("quarter_steps")) s.step_scale = 0.25;
  const GrazingRow row = grazing_row(b, s);
  r.m["steps"] = row.steps;
  r.m["law"] = law;
  r.m["steps_over_law"] = row.steps / law;
  r.require("no_hit", row.outcome != Outcome::hit, "a hit on a ray that passes b above the sphere (hit_eps is b / 1000)");
  r.require("decided", row.outcome == Outcome::miss_far || row.outcome == Outcome::hit,
            "undecided: max_steps ran out before the ray got past");
  // The band the convergence test uses: the law counts the steps near the sphere; approach and exit add a few.
  if (row.outcome == Outcome::miss_far)
    r.require("steps_law", row.steps > 0.5 * law && row.steps < 1.5 * law + 20, "steps outside [0.5 law, 1.5 law + 20]");
}

void incidence(Run& r, double deg) {
  const double s = std::sin(deg * kPi / 180), c = std::cos(deg * kPi / 180), h0 = 1, eps = 1e-4;
  const double law = std::log(eps / h0) / std::log(1 - s);
  const sdf::Tape tape = sdf::compile(sdf::plane({0, 1, 0}, 0));
  MarchSettings ms;
  ms.hit_eps = eps;
  ms.max_dist = 1e7;
  ms.max_steps = r.naive() ? static_cast<int>(law / 2) : 1 << 22;
  if (r.as("half_steps")) ms.step_scale = 0.5;
  auto rec = march::march<double>(TapeField{&tape}, dvec3(0, h0, 0), dvec3(c, -s, 0), ms, {});
  if (r.as("hit_lifted")) rec.t -= eps / s;  // a self-shadowing fix made on t: the hit lifted hit_eps off the plane
  const double t_err = std::abs(rec.t - h0 / s);
  r.m["steps"] = rec.steps;
  r.m["law"] = law;
  r.m["t_err"] = t_err;
  r.m["t_err_bound"] = eps / s;
  r.require("hit", rec.outcome == Outcome::hit, "the ray did not reach the plane: " + std::string(march::to_string(rec.outcome)));
  if (rec.outcome != Outcome::hit) return;
  // Each step keeps 1 - sin(theta) of the height: the hit comes on the first whole step past the law, plus the
  // evaluation that sees it.
  r.require("steps_law", std::abs(rec.steps - law) <= 2, "steps " + num(rec.steps) + " off the law " + num(law));
  // The march stops less than hit_eps above the plane, which is hit_eps / sin(theta) along the ray.
  r.require("t_err", t_err <= eps / s, "t error above hit_eps / sin(theta)");
}

// ---- rays starting in, on and just above a surface ----

enum class Start { inside, on, half_eps };

void start_case(Run& r, Start where) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const TapeField field{&tape};
  MarchSettings ms;
  ms.hit_eps = 1e-3;
  const float x = where == Start::inside ? 0.5f : where == Start::on ? 1.0f : 1.0005f;
  const Outcome expected = where == Start::inside ? Outcome::inside : Outcome::hit;
  int wrong_outcome = 0, wrong_t = 0, wrong_evals = 0;
  for (const float dir : {1.0f, -1.0f}) {
    const vec3 origin(x, 0, 0), d(dir, 0, 0);
    // naive: the skip-ahead workaround for self-hits (start hit_eps along the ray), or the shader loop inside;
    // skip_leaving: the skip-ahead on rays leaving the surface only, a quarter of hit_eps
    const float t_start = r.naive() ? float(ms.hit_eps) : r.as("skip_leaving") && dir > 0 ? float(ms.hit_eps) / 4 : 0;
    march::RayRecord<float> rec = (r.naive() && where == Start::inside) || r.as("shader_loop")
                                      ? naive_march<float>(field, origin, d, ms)
                                      : march::march<float>(field, origin, d, ms, {}, t_start);
    if (r.as("inside_below_eps") && field(origin) < float(ms.hit_eps)) rec.outcome = Outcome::inside;  // hit and
                                                                                                      // inside split at hit_eps, not 0
    if (r.as("inside_test_first")) ++rec.evals;  // the start evaluated once for an inside test, again in the loop
    wrong_outcome += rec.outcome != expected;
    wrong_t += rec.t != 0;
    wrong_evals += rec.evals != 1;
    r.m[dir > 0 ? "outward.t" : "inward.t"] = rec.t;
    r.m[dir > 0 ? "outward.outcome" : "inward.outcome"] = static_cast<double>(rec.outcome);
  }
  r.m["wrong"] = wrong_outcome + wrong_t + wrong_evals;
  r.require("outcome", wrong_outcome == 0, std::to_string(wrong_outcome) + " of 2 rays not reported " +
                                               (where == Start::inside ? "inside" : "hit"));
  r.require("t_zero", wrong_t == 0, std::to_string(wrong_t) + " of 2 rays not at t = 0");
  r.require("one_eval", wrong_evals == 0, std::to_string(wrong_evals) + " of 2 rays took other than one evaluation");
}

// ---- shadow rays from marched hit points: self-hits per bias strategy ----

// Lit points on a lone sphere (convex: nothing can shadow them) whose shadow ray is blocked anyway.
int self_hits(double radius, sdf::ShadowBias bias, bool no_bias, int& lit) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(radius));
  const TapeField field{&tape};
  MarchSettings ms;
  ms.hit_eps = 1e-3;
  ms.max_dist = 10 * radius;
  ms.max_steps = 1000;
  sdf::Light light;
  light.shadow = sdf::ShadowMode::hard;
  light.bias = bias;
  const vec3 to_light = glm::normalize(vec3(0.3f, 0.5f, 1.0f));
  const dvec3 eye(0, 0, 3 * radius);
  int blocked = 0;
  lit = 0;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i) {
      const dvec3 target((i - 5.5) / 8 * radius, (j - 5.5) / 8 * radius, 0);
      const vec3 d(glm::normalize(target - eye));
      const auto rec = march::march<float>(field, vec3(eye), d, ms, {});
      if (rec.outcome != Outcome::hit) continue;
      const vec3 p = vec3(eye) + d * rec.t;
      const vec3 n = march::estimate_normal(field, p, sdf::NormalMethod::central, float(1e-3 * radius)).n;
      if (glm::dot(n, to_light) < 0.1f) continue;
      ++lit;
      if (no_bias) {
        const auto s = march::march<float>(field, p, to_light, ms, {});
        blocked += s.outcome == Outcome::hit || s.outcome == Outcome::inside;
      } else {
        blocked += march::shadow_visibility<float>(field, p, n, to_light, std::numeric_limits<float>::infinity(),
                                                   rec.t, light, ms, {})
                       .visibility < 0.5;
      }
    }
  return blocked;
}

void shadow_case(Run& r, sdf::ShadowBias bias, double radius) {
  int lit = 0;
  const int hits = self_hits(radius, bias, r.naive(), lit);
  r.m["lit_points"] = lit;
  r.m["self_hits"] = hits;
  if (radius > 1) {  // the other strategies at this scale, for comparison
    int unused = 0;
    r.m["seed_offset.self_hits"] = self_hits(radius, sdf::ShadowBias::seed_offset, false, unused);
    r.m["seed_ignore.self_hits"] = self_hits(radius, sdf::ShadowBias::seed_ignore, false, unused);
  }
  r.needs("lit_points", lit >= 20, "too few lit hit points to test");
  r.require("no_self_hit", hits == 0, std::to_string(hits) + " shadow rays re-hit their own surface");
}

// ---- far coordinates: float, double and the camera-relative fix ----

struct FarErrors {
  double t_err = 0, normal_deg = 0;
  int missed = 0, t_off = 0, normal_off = 0;  // rays that did not hit; hits beyond the t bound; beyond 1 degree
  int wrong = 0;                              // rays with any of the three
};

// The broken variants of one precision's march: no budget, the hit lifted off the surface, a facing normal.
enum class FarBreak { none, one_step, hit_lifted, normal_facing };

FarBreak far_break(const Run& r, const std::string& precision) {
  for (const auto& [name, kind] : {std::pair{".one_step", FarBreak::one_step}, std::pair{".hit_lifted", FarBreak::hit_lifted},
                                   std::pair{".normal_facing", FarBreak::normal_facing}})
    if (r.as(precision + name)) return kind;
  return FarBreak::none;
}

constexpr double kFarEps = 1e-4;

// A unit sphere at offset seen from 4 units away: rays marched in T, in world coordinates or camera-relative.
template <class T>
FarErrors far_errors(dvec3 offset, bool relative, FarBreak broken = FarBreak::none) {
  using V = glm::vec<3, T>;
  const sdf::Node world = sdf::translate(offset, sdf::sphere(1));
  const dvec3 eye = offset + dvec3(0, 0, 4);
  const sdf::Tape tape = sdf::compile(relative ? march::camera_relative(world, eye) : world);
  const TapeField field{&tape};
  const Reference ref(world, 0);
  MarchSettings ms;
  ms.hit_eps = kFarEps;
  ms.max_steps = broken == FarBreak::one_step ? 1 : 1000;
  FarErrors out;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) {
      const dvec3 d = glm::normalize(offset + dvec3((i - 2.5) / 4, (j - 2.5) / 4, 0) - eye);
      const ReferenceHit exact = ref.first_hit(eye, d, 100);
      const V origin = relative ? V(0) : V(eye);
      auto rec = march::march<T>(field, origin, V(d), ms, {});
      if (rec.outcome != Outcome::hit) {
        ++out.missed;
        ++out.wrong;
        continue;
      }
      if (broken == FarBreak::hit_lifted) rec.t -= T(10 * kFarEps);  // backed off 10 hit_eps along the ray
      const double t_err = std::abs(double(rec.t) - exact.t);
      const double cos_i = -glm::dot(d, exact.normal);
      const dvec3 n = broken == FarBreak::normal_facing
                          ? -d  // the shortcut "the surface faces the eye"
                          : dvec3(march::estimate_normal(field, origin + V(d) * rec.t, sdf::NormalMethod::central, T(1e-3)).n);
      const double nd = glm::dot(n, n) > 0 ? angle_deg(n, exact.normal) : 180.0;
      // hit_eps along the normal is hit_eps / cos along the ray; 1e-5 covers float rounding of local coordinates
      // (|q| <= 5, float epsilon 1.2e-7, a few dozen operations). Central differences at 1e-3 on a unit sphere
      // are far under a degree off.
      const bool t_off = t_err > kFarEps / cos_i + 1e-5, normal_off = !(nd <= 1);
      out.t_off += t_off;
      out.normal_off += normal_off;
      out.wrong += t_off || normal_off;
      out.t_err = std::max(out.t_err, t_err);
      out.normal_deg = std::max(out.normal_deg, nd);
    }
  return out;
}

void far_record(Run& r, const std::string& prefix, const FarErrors& e) {
  r.m[prefix + ".t_err"] = e.t_err;
  r.m[prefix + ".normal_err_deg"] = e.normal_deg;
  r.m[prefix + ".wrong"] = e.wrong;
}

// One precision's three clauses at one offset: every ray hits, within the t bound, with its normal within 1 degree.
void far_require(Run& r, const std::string& precision, dvec3 offset, const FarErrors& e) {
  const std::string at = precision + " at offset " + num(glm::length(offset)) + ": ";
  r.require(precision + ".hits", e.missed == 0, at + std::to_string(e.missed) + " rays missed");
  r.require(precision + ".t", e.t_off == 0, at + std::to_string(e.t_off) + " hits beyond hit_eps / cos + 1e-5");
  r.require(precision + ".normal", e.normal_off == 0, at + std::to_string(e.normal_off) + " normals off by over 1 degree");
}

// The variants that break one clause of far_require in one precision.
std::vector<StabilityVariant> far_variants(const std::string& precision) {
  return {{precision + ".one_step", precision + ".hits", precision + " marched with max_steps 1"},
          {precision + ".hit_lifted", precision + ".t", precision + " hits backed off 10 hit_eps along the ray"},
          {precision + ".normal_facing", precision + ".normal", precision + " normals taken as the ray reversed"}};
}

// The renderer's answer (camera-relative float; naive: float in world coordinates) and double must hold.
void far_offsets(Run& r, const std::vector<dvec3>& offsets, bool label_by_decade) {
  for (const dvec3& off : offsets) {
    const std::string at = label_by_decade ? decade(glm::length(off)) + "." : "";
    const FarErrors fl = far_errors<float>(off, !r.naive(), far_break(r, "float"));
    const FarErrors db = far_errors<double>(off, false, far_break(r, "double"));
    far_record(r, at + (r.naive() ? "float_world" : "float_camera_relative"), fl);
    far_record(r, at + "double", db);
    far_require(r, "float", off, fl);
    far_require(r, "double", off, db);
  }
}

std::vector<dvec3> decade_offsets() {
  std::vector<dvec3> out;
  for (int k = 1; k <= 7; ++k) out.push_back(dvec3(1, 1, 1) * (std::pow(10.0, k) / std::sqrt(3.0)));
  return out;
}

// Double holds at every offset; float in world coordinates breaks down where its spacing passes hit_eps.
void far_double(Run& r, const StabilityOptions&) {
  double breakdown = 0, predicted = 0;
  for (const dvec3& off : decade_offsets()) {
    // Float's spacing at the coordinates: once it passes hit_eps, rounding alone moves hits off by more.
    const float c = static_cast<float>(off.x);
    if (predicted == 0 && std::nextafter(c, INFINITY) - c > kFarEps) predicted = glm::length(off);
    const std::string at = decade(glm::length(off)) + ".";
    const FarErrors fl = far_errors<float>(off, false);
    const FarErrors db = r.naive() ? fl : far_errors<double>(off, false, far_break(r, "double"));
    far_record(r, at + "float_world", fl);
    far_record(r, at + (r.naive() ? "float_as_double" : "double"), db);
    if (fl.wrong > 0 && breakdown == 0) breakdown = glm::length(off);
    far_require(r, "double", off, db);
  }
  r.m["float_world.breakdown_offset"] = breakdown;
  r.m["float_world.breakdown_predicted"] = predicted;
}

// ---- scales from 1e-8 to 1e8 ----

// A sphere of radius S seen from 4 S: rays through its inner disk must hit within the threshold, rays past its
// silhouette must miss. Records the worst relative t error and each clause's count of wrong rays.
void scale_errors(Run& r, const std::string& label, double scale, march::EpsMode mode) {
  const sdf::Node node = sdf::sphere(scale);
  const sdf::Tape tape = sdf::compile(node);
  const TapeField field{&tape};
  const Reference ref(node, 0);
  sdf::CameraSpec spec;
  spec.position = {0, 0, 4 * scale};
  spec.fov_deg = 40;
  const march::Camera camera(spec, 64, 64);
  const march::MarchContext ctx = march::march_context(camera);
  MarchSettings ms;
  ms.eps_mode = r.naive() ? march::EpsMode::absolute : mode;
  ms.hit_eps = r.naive() ? 1e-3 : 1e-4;  // naive: the absolute epsilon that suits unit scenes
  ms.max_dist = 10 * scale;
  ms.max_steps = 1000;
  const double reference_max_dist = ms.max_dist;
  if (r.as("max_dist_short")) ms.max_dist = 2 * scale;  // a max_dist left unscaled: short of the sphere at 3 S
  int missed = 0, t_off = 0, outer_hit = 0;
  double worst = 0;
  const dvec3 eye = spec.position;
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 7; ++i) {
      // Inner disk (radius 0.8 S at the centre plane) and a ring outside the silhouette (1.3 S).
      const double a = 2 * kPi * (i + 7 * j) / 49, rr = (i + j) % 2 ? 0.8 * scale * (j + 1) / 7 : 1.3 * scale;
      const dvec3 d = glm::normalize(dvec3(rr * std::cos(a), rr * std::sin(a), 0) - eye);
      const ReferenceHit exact = ref.first_hit(eye, d, reference_max_dist);
      auto rec = march::march<float>(field, vec3(eye), vec3(d), ms, ctx);
      if (r.as("miss_as_hit") && rec.outcome == Outcome::miss_far) rec.outcome = Outcome::hit;  // t < inf read as a hit
      if (!exact.hit) {
        outer_hit += rec.outcome != Outcome::miss_far;
        continue;
      }
      if (rec.outcome != Outcome::hit) {
        ++missed;
        continue;
      }
      // hit_lifted: the hit backed off 10 thresholds along the ray
      if (r.as("hit_lifted")) rec.t -= 10 * static_cast<float>(march::hit_threshold(ms, ctx, rec.t));
      const double rel = std::abs(double(rec.t) - exact.t) / exact.t;
      const double cos_i = -glm::dot(d, exact.normal);
      // The threshold along the normal is threshold / cos along the ray; float rounds |p| (about 4 S) to
      // 4 epsilon relative at most over the few operations of one evaluation.
      const double bound = march::hit_threshold(ms, ctx, exact.t) / cos_i / exact.t + 4 * kFloatEps * 4;
      t_off += !(rel <= bound);
      worst = std::max(worst, rel);
    }
  r.m[label + ".scale"] = scale;
  r.m[label + ".t_rel_err"] = worst;
  r.m[label + ".wrong"] = missed + t_off + outer_hit;
  const std::string at = " at scale " + num(scale);
  r.require("inner.hits", missed == 0, std::to_string(missed) + " inner rays missed" + at);
  r.require("inner.t", t_off == 0, std::to_string(t_off) + " inner hits beyond threshold / cos" + at);
  r.require("outer.miss", outer_hit == 0, std::to_string(outer_hit) + " rays past the silhouette did not miss" + at);
}

void scale_case(Run& r, march::EpsMode mode, const std::vector<double>& scales) {
  for (size_t i = 0; i < scales.size(); ++i)
    scale_errors(r, scales.size() == 1 ? decade(scales[i]) : "s" + std::to_string(i), scales[i], mode);
}

std::vector<double> log_uniform_scales() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-8, 8);
  std::vector<double> out;
  for (int i = 0; i < 12; ++i) out.push_back(std::pow(10.0, u(rng)));
  return out;
}

// ---- thin features and coincident surfaces ----

// Rays along -z at x across [x0, x1] (y fixed) against the reference: same hit or miss, t within hit_eps / cos.
void thin_rays(Run& r, const sdf::Node& node, double x0, double x1, double y, double z0) {
  const sdf::Tape tape = sdf::compile(node);
  const Reference ref(node, 0);
  MarchSettings ms;
  ms.hit_eps = 1e-5;
  ms.max_steps = 2000;
  ms.max_dist = 10;
  if (r.naive()) {  // the classic fixed-step ray marcher
    ms.marcher = march::Marcher::fixed;
    ms.fixed_step = 0.01;
  }
  int disagree = 0, t_off = 0, hits = 0;
  double worst = 0;
  const dvec3 d(0, 0, -1);
  for (int i = 0; i <= 20; ++i) {
    const dvec3 o(x0 + (x1 - x0) * i / 20, y, z0);
    const ReferenceHit exact = ref.first_hit(o, d, ms.max_dist);
    auto rec = march::march<float>(TapeField{&tape}, vec3(o), vec3(d), ms, {});
    if (r.as("miss_as_hit") && rec.outcome == Outcome::miss_far) rec.outcome = Outcome::hit;  // t < inf read as a hit
    if ((rec.outcome == Outcome::hit) != exact.hit) {
      ++disagree;
      continue;
    }
    if (!exact.hit) continue;
    ++hits;
    if (r.as("hit_lifted")) rec.t -= 100 * float(ms.hit_eps);  // backed off 100 hit_eps along the ray
    const double err = std::abs(double(rec.t) - exact.t);
    worst = std::max(worst, err);
    // hit_eps / cos, plus the reference's own bound and float rounding at |p| <= 4 (1e-6).
    t_off += !(err <= ms.hit_eps / std::max(-glm::dot(d, exact.normal), 0.05) + ref.t_error_bound() + 1e-6);
  }
  r.m["rays"] = 21;
  r.m["hits"] = hits;
  r.m["wrong"] = disagree + t_off;
  r.m["t_err_max"] = worst;
  r.needs("feature_hit", hits > 0, "no ray hit the feature");
  r.require("agree", disagree == 0, std::to_string(disagree) + " of 21 rays missed the feature or hit nothing there");
  r.require("t", t_off == 0, std::to_string(t_off) + " of 21 rays hit beyond hit_eps / cos");
}

// Rays from above onto coincident tops: hits at y = top within hit_eps, normals +y within a degree, never NaN.
void coincident(Run& r, double gap) {
  const sdf::Node node = sdf::unite({sdf::translate({-1, 0, 0}, sdf::box({1, 1, 1})),
                                     sdf::translate({1, gap, 0}, sdf::box({1, 1, 1}))});
  const sdf::Tape tape = sdf::compile(node);
  const TapeField field{&tape};
  MarchSettings ms;
  ms.hit_eps = 1e-4;
  if (r.as("one_step")) ms.max_steps = 1;
  int missed = 0, t_off = 0, normal_off = 0;
  double worst_t = 0, worst_n = 0;
  for (int i = 0; i <= 20; ++i) {
    const vec3 o(-0.01f + 0.001f * static_cast<float>(i), 3, 0.3f), d(0, -1, 0);
    auto rec = march::march<float>(field, o, d, ms, {});
    if (rec.outcome != Outcome::hit) {
      ++missed;
      continue;
    }
    if (r.as("hit_lifted")) rec.t -= 10 * float(ms.hit_eps);  // backed off 10 hit_eps along the ray
    const vec3 p = o + d * rec.t;
    // naive: the raw gradient normalised, with an epsilon under float's spacing at 1 (0 / 0 on flat faces)
    const vec3 n = r.naive() ? glm::normalize(vec3(field(p + vec3(1e-9f, 0, 0)) - field(p - vec3(1e-9f, 0, 0)),
                                                   field(p + vec3(0, 1e-9f, 0)) - field(p - vec3(0, 1e-9f, 0)),
                                                   field(p + vec3(0, 0, 1e-9f)) - field(p - vec3(0, 0, 1e-9f))))
                             : march::estimate_normal(field, p, sdf::NormalMethod::central, 1e-3f).n;
    const double top = o.x > 0 ? 1 + gap : 1;
    const double t_err = std::abs(double(rec.t) - (3 - top));
    const double n_err = glm::dot(n, n) > 0 ? angle_deg(dvec3(n), {0, 1, 0}) : 180;
    worst_t = std::max(worst_t, t_err);
    worst_n = std::isnan(n_err) ? NAN : std::max(worst_n, n_err);
    // hit_eps head-on plus the gap itself (either top is a right answer within it); normals: the seam's edge is
    // more than normal_eps below the top, so both sides see a flat face.
    t_off += !(t_err <= ms.hit_eps + gap + 1e-6);
    normal_off += !(n_err <= 1);
  }
  r.m["t_err_max"] = worst_t;
  r.m["normal_err_max_deg"] = worst_n;
  r.m["wrong"] = missed + t_off + normal_off;
  r.require("hits", missed == 0, std::to_string(missed) + " of 21 rays missed");
  r.require("t", t_off == 0, std::to_string(t_off) + " of 21 rays hit off the top by more than hit_eps + gap");
  r.require("normal", normal_off == 0, std::to_string(normal_off) + " of 21 normals off +y by over 1 degree (or NaN)");
}

// A sphere smaller than hit_eps: rays passing within hit_eps of it "hit"; the case must report the object as
// unresolvable at this threshold rather than count those as hits.
void tiny(Run& r) {
  const sdf::Node node = sdf::sphere(1e-5);
  const sdf::Tape tape = sdf::compile(node);
  const Reference ref(node, 0);
  MarchSettings ms;
  ms.hit_eps = 1e-3;
  const dvec3 size = sdf::derive_info(node).bounds.size();
  const bool flagged = !r.naive() && std::max({size.x, size.y, size.z}) < ms.hit_eps;
  int false_hits = 0, unexplained = 0;
  for (int i = 0; i <= 20; ++i) {
    const double miss = 2e-3 * i / 20;  // closest approach to the centre
    const dvec3 o(miss, 0, -1), d(0, 0, 1);
    const auto rec = march::march<double>(TapeField{&tape}, o, d, ms, {});
    const bool exact_hit = ref.first_hit(o, d, 10).hit;
    if (rec.outcome == Outcome::hit && !exact_hit) {
      ++false_hits;
      // Explained only when the object is flagged as under hit_eps and the ray passed within hit_eps of it.
      unexplained += !(flagged && miss - 1e-5 < ms.hit_eps);
    }
  }
  r.m["object_size"] = std::max({size.x, size.y, size.z});
  r.m["hit_eps"] = ms.hit_eps;
  r.m["flagged_below_hit_eps"] = flagged;
  r.m["false_hits"] = false_hits;
  r.m["unexplained_hits"] = unexplained;
  r.needs("false_hits", false_hits > 0, "no ray hit within hit_eps of the tiny object: the case tests nothing");
  r.require("explained", unexplained == 0, std::to_string(unexplained) + " hits on an object smaller than hit_eps went unreported");
}

// ---- normals at sharp features ----

// The angle from n to the cone of the sides' normals (their non-negative combinations; 0 inside it). On a sharp
// feature the gradient is undefined and every normal in that cone is a right answer.
double cone_angle_deg(dvec3 n, const std::vector<dvec3>& sides) {
  double best = 180;
  for (const dvec3& s : sides) best = std::min(best, angle_deg(n, s));
  for (size_t i = 0; i < sides.size(); ++i)
    for (size_t j = i + 1; j < sides.size(); ++j) {  // n projected onto the plane of two sides, if between them
      const dvec3 a = sides[i], b = sides[j];
      const double aa = glm::dot(a, a), ab = glm::dot(a, b), bb = glm::dot(b, b), det = aa * bb - ab * ab;
      const double alpha = (glm::dot(n, a) * bb - glm::dot(n, b) * ab) / det;
      const double beta = (glm::dot(n, b) * aa - glm::dot(n, a) * ab) / det;
      if (det > 0 && alpha >= 0 && beta >= 0 && alpha + beta > 0) best = std::min(best, angle_deg(n, alpha * a + beta * b));
    }
  if (sides.size() == 3) {  // inside the cone of three
    const glm::dmat3 basis(sides[0], sides[1], sides[2]);
    const dvec3 c = glm::inverse(basis) * n;
    if (glm::determinant(basis) != 0 && c.x >= 0 && c.y >= 0 && c.z >= 0) best = 0;
  }
  return best;
}

// Central-difference normals at points on a sharp feature: finite, unit, and inside the feature's normal cone
// (within a degree); at points 2 normal_eps off it, within a degree of their side's normal.
void sharp_normals(Run& r, const sdf::Node& node, const std::vector<dvec3>& on, const std::vector<dvec3>& off,
                   const std::function<std::vector<dvec3>(dvec3)>& sides) {
  const sdf::Tape tape = sdf::compile(node);
  const TapeField field{&tape};
  const float eps = r.as("wide_eps") ? 0.05f : 1e-3f;  // wide_eps: 50 normal_eps, wider than the gap to the feature
  const auto gradient = [&](vec3 q, float e) {
    return vec3(field(q + vec3(e, 0, 0)) - field(q - vec3(e, 0, 0)), field(q + vec3(0, e, 0)) - field(q - vec3(0, e, 0)),
                field(q + vec3(0, 0, e)) - field(q - vec3(0, 0, e))) / (2 * e);
  };
  const auto normal = [&](dvec3 p, const std::vector<dvec3>& at, bool on_feature) {
    const vec3 q(p);
    if (r.naive()) return dvec3(glm::normalize(gradient(q, 1e-9f)));  // epsilon under float's spacing: 0 / 0
    if (r.as("unnormalised")) return dvec3(gradient(q, eps));
    if (r.as("inward_on_feature") && on_feature) {  // a wrong tie-break where the sides meet: into the solid
      dvec3 sum(0);
      for (const dvec3& s : at) sum += glm::normalize(s);
      return -glm::normalize(sum);
    }
    return dvec3(march::estimate_normal(field, q, sdf::NormalMethod::central, eps).n);
  };
  int bad = 0;
  // On the feature: the angle to its normal cone; beside it: to the nearest side's normal.
  const auto worst = [&](const std::vector<dvec3>& pts, bool on_feature) {
    double w = 0;
    for (const dvec3& p : pts) {
      const std::vector<dvec3> at = sides(p);
      const dvec3 n = normal(p, at, on_feature);
      if (!std::isfinite(n.x + n.y + n.z) || std::abs(glm::length(n) - 1) > 1e-5) ++bad;
      if (!std::isfinite(n.x + n.y + n.z) || glm::dot(n, n) == 0) continue;  // no direction to judge
      double angle = on_feature ? cone_angle_deg(n, at) : 180;
      if (!on_feature)
        for (const dvec3& s : at) angle = std::min(angle, angle_deg(n, s));
      w = std::max(w, angle);
    }
    return w;
  };
  const double on_err = worst(on, true), off_err = worst(off, false);
  r.m["on_feature.cone_angle_max_deg"] = on_err;
  r.m["off_feature.angle_max_deg"] = off_err;
  r.m["normals_not_unit"] = bad;
  r.require("finite_unit", bad == 0, std::to_string(bad) + " normals NaN, infinite or not unit length");
  r.require("on_feature", on_err <= 1, "on the feature: " + num(on_err) + " degrees outside the normal cone");
  r.require("off_feature", off_err <= 1, "2 normal_eps off the feature: " + num(off_err) + " degrees off the side's normal");
}

void box_normals(Run& r, bool corner) {
  std::vector<dvec3> on, off;
  for (int i = 0; i <= 10; ++i) {
    const double y = corner ? 1 : -0.5 + 0.1 * i;
    on.push_back(corner ? dvec3(1, 1, 1) * (1 - 1e-8 * i) : dvec3(1, y, 1));
    off.push_back(corner ? dvec3(1 - 2e-3 - 1e-2 * i, 1 - 2e-3, 1) : dvec3(1 - 2e-3 - 1e-2 * i, y, 1));
  }
  const auto sides = [](dvec3 p) {
    std::vector<dvec3> s;
    if (p.x > 1 - 1e-6) s.push_back({1, 0, 0});
    if (p.y > 1 - 1e-6) s.push_back({0, 1, 0});
    if (p.z > 1 - 1e-6) s.push_back({0, 0, 1});
    return s;
  };
  sharp_normals(r, sdf::box({1, 1, 1}), on, off, sides);
}

void seam_normals(Run& r, const StabilityOptions&) {
  // Two unit spheres at x = -0.5 and 0.5: the seam is the circle x = 0, radius sqrt(0.75).
  const sdf::Node node = sdf::unite({sdf::translate({-0.5, 0, 0}, sdf::sphere(1)), sdf::translate({0.5, 0, 0}, sdf::sphere(1))});
  std::vector<dvec3> on, off;
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * kPi * i / 12, rr = std::sqrt(0.75);
    on.push_back({0, rr * std::cos(a), rr * std::sin(a)});
    const dvec3 q = dvec3(0.5, 0, 0) + glm::normalize(dvec3(-0.5 + 0.01, rr * std::cos(a), rr * std::sin(a)));
    off.push_back(q);
  }
  // On the seam: both spheres' normals (60 degrees apart); beside it, the nearer one's is the closer.
  const auto sides = [](dvec3 p) { return std::vector<dvec3>{p - dvec3(-0.5, 0, 0), p - dvec3(0.5, 0, 0)}; };
  sharp_normals(r, node, on, off, sides);
}

// ---- non-Lipschitz fields ----

// Plain sphere tracing overshoots on a field steeper than 1; the scaled marcher with the measured L does not.
// An overshoot: a hit that ended deeper than hit_eps inside, a hit beyond the first surface, or a miss through it.
void lipschitz_case(Run& r, sdf::Scene scene, dvec3 lo, dvec3 hi) {
  const sdf::Tape tape = sdf::compile(scene.root, scene.time);
  const TapeField field{&tape};
  const double measured = sdf::measured_slope([&](dvec3 p) { return field(p); }, lo, hi, 20000, 1e-5);
  const Reference ref(scene.root, scene.time);
  const march::Camera camera(scene.camera, 32, 18);
  const double max_dist = std::min(scene.march.max_dist, 50.0);
  const auto count = [&](march::Marcher m, double lipschitz, double& evals) {
    MarchSettings ms = scene.march;
    ms.marcher = m;
    ms.max_dist = max_dist;
    ms.max_steps = 2000;
    march::MarchContext ctx;
    ctx.lipschitz = lipschitz;
    int over = 0;
    evals = 0;
    for (int j = 0; j < 18; ++j)
      for (int i = 0; i < 32; ++i) {
        const march::Ray ray = camera.ray(i + 0.5, j + 0.5);
        const dvec3 d = glm::normalize(ray.direction);
        const auto rec = march::march<double>(field, ray.origin, d, ms, ctx);
        evals += rec.evals;
        const ReferenceHit exact = ref.first_hit(ray.origin, d, max_dist);
        if (exact.unknown) continue;
        const double eps = march::hit_threshold(ms, ctx, rec.t);
        const bool hit = rec.outcome == Outcome::hit;
        // 0.01: far past hit_eps / cos at every incidence these scenes show, and under any feature's size.
        over += (hit && rec.last_abs_f > eps) || (hit && exact.hit && rec.t > exact.t + 0.01) ||
                (rec.outcome == Outcome::miss_far && exact.hit);
      }
    evals /= 32 * 18;
    return over;
  };
  double plain_evals = 0, scaled_evals = 0;
  const int plain = count(march::Marcher::sphere, 1, plain_evals);
  const int scaled = count(march::Marcher::scaled, r.naive() ? 1 : measured, scaled_evals);
  r.m["lipschitz.measured"] = measured;
  r.m["lipschitz.declared"] = sdf::derive_info(scene.root, scene.time).lipschitz;
  r.m["plain.overshoots"] = plain;
  r.m["scaled.overshoots"] = scaled;
  r.m["plain.evals_per_ray"] = plain_evals;
  r.m["scaled.evals_per_ray"] = scaled_evals;
  r.needs("steep", measured > 1, "the field measures 1-Lipschitz: nothing to test");
  r.needs("plain_overshoots", plain > 0, "plain sphere tracing showed no overshoot: the case cannot tell the marchers apart");
  r.require("no_overshoot", scaled == 0, std::to_string(scaled) + " overshoots left with steps f / L");
}

sdf::Scene twist_scene() {
  sdf::Scene s;
  s.name = "twist";
  s.root = sdf::make(sdf::Op::twist, {{"rate", {4}}}, {sdf::box({0.6, 1.2, 0.15})});
  s.camera.position = {0.3, 0.2, 3};
  s.camera.fov_deg = 50;
  s.march.hit_eps = 1e-4;
  return s;
}

// ---- the Mandelbulb far out and deep ----

// The textbook estimator (no guard at the origin, powers taken as they come), for the naive variants.
double textbook_mandelbulb(dvec3 p, int iterations) {
  dvec3 w = p;
  double dr = 1, r = 0;
  for (int i = 0; i < iterations; ++i) {
    r = glm::length(w);
    if (r > 2) break;
    const double theta = std::acos(w.y / r) * 8, phi = std::atan2(w.x, w.z) * 8;
    dr = 8 * std::pow(r, 7) * dr + 1;
    w = p + std::pow(r, 8) * dvec3(std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi));
  }
  return 0.5 * std::log(r) * r / dr;
}

void mandelbulb_far(Run& r, const StabilityOptions&) {
  const sdf::Node bulb = sdf::make(sdf::Op::mandelbulb, {{"iterations", {8}}});
  const sdf::Tape tape = sdf::compile(bulb);
  int bad = 0, samples = 0;
  for (int k = 1; k <= 37; ++k)
    for (const dvec3 dir : {dvec3(1, 0, 0), dvec3(0, 1, 0), glm::normalize(dvec3(1, -2, 3))}) {
      const dvec3 p = dir * std::pow(10.0, k);
      const float vf = r.naive() ? static_cast<float>(textbook_mandelbulb(p, 8)) : sdf::evaluate(tape, vec3(p));
      const double vd = r.naive() ? textbook_mandelbulb(p, 8) : sdf::evaluate(tape, p);
      samples += 2;
      // The set lies within 1.25 of the origin, so a sane estimate far out is positive and finite.
      bad += !(std::isfinite(vf) && vf > 0) + !(std::isfinite(vd) && vd > 0);
    }
  // A march from 1e5 away in float ends decided or honestly undecided, never on a non-finite value.
  MarchSettings ms;
  ms.marcher = march::Marcher::scaled;
  ms.max_dist = 2e5;
  ms.hit_eps = 1e-3;
  ms.max_steps = 2000;
  march::MarchContext ctx;
  ctx.lipschitz = r.as("lipschitz_zero") ? 0 : 2;  // lipschitz_zero: a field's constant left at 0, steps f / 0
  const auto rec = march::march<float>(TapeField{&tape}, vec3(0, 0, 1e5f), vec3(0, 0, -1), ms, ctx);
  r.m["samples"] = samples;
  r.m["non_finite_or_negative"] = bad;
  r.m["march_from_1e5.outcome"] = static_cast<double>(rec.outcome);
  r.m["march_from_1e5.t"] = rec.t;
  r.require("far_finite", bad == 0, std::to_string(bad) + " of " + std::to_string(samples) +
                                        " far samples (1e1..1e37, float and double) not finite and positive");
  r.require("march_finite", rec.outcome != Outcome::invalid && std::isfinite(rec.t),
            "the march from 1e5 met a non-finite value");
}

void mandelbulb_deep(Run& r, const StabilityOptions&) {
  const sdf::Node bulb = sdf::make(sdf::Op::mandelbulb, {{"iterations", {64}}});
  const sdf::Tape tape = sdf::compile(bulb);
  int bad = 0, samples = 0;
  for (int i = -6; i <= 6; ++i)
    for (int j = -6; j <= 6; ++j)
      for (int k = -6; k <= 6; ++k) {
        const dvec3 p = dvec3(i, j, k) * 0.22;  // includes the origin, where the angles are undefined
        const double vd = r.naive() ? textbook_mandelbulb(p, 64) : sdf::evaluate(tape, p);
        const float vf = r.naive() ? static_cast<float>(vd) : sdf::evaluate(tape, vec3(p));
        samples += 2;
        bad += !std::isfinite(vd) + !std::isfinite(vf);
      }
  r.m["iterations"] = 64;
  r.m["samples"] = samples;
  r.m["non_finite"] = bad;
  r.require("finite", bad == 0, std::to_string(bad) + " of " + std::to_string(samples) + " samples at 64 iterations not finite");
}

// ---- degenerate rays and settings ----

struct BadRay {
  vec3 origin, direction;
};

MarchSettings input_settings() {
  MarchSettings ms;
  ms.hit_eps = 1e-3;
  ms.max_steps = 1000;
  ms.max_dist = 100;
  return ms;
}

const vec3 kCleanOrigin(0.3f, 0.2f, -3.0f), kCleanDir(0, 0, 1);

// The marcher a degenerate-input case runs: as it is, the shader loop (naive), or one bookkeeping mistake.
template <class F>
march::RayRecord<float> march_input(const Run& r, const F& f, vec3 o, vec3 d, const MarchSettings& ms) {
  if (r.naive()) return naive_march<float>(f, o, d, ms);
  auto rec = march::march<float>(f, o, d, ms, {});
  const bool ran_out = rec.outcome == Outcome::miss_steps;
  if (r.as("invalid_as_miss") && rec.outcome == Outcome::invalid) rec.outcome = Outcome::miss_far;
  if (r.as("no_early_exit")) rec.evals = std::max(ms.max_steps, 0);  // a fixed trip count, bad input flagged after
  if (r.as("miss_at_infinity") && (ran_out || rec.outcome == Outcome::miss_far))  // Embree's tfar convention
    rec.t = std::numeric_limits<float>::infinity();
  if (r.as("ran_out_as_hit") && ran_out) rec.outcome = Outcome::hit;
  if (r.as("ran_out_as_miss_far") && ran_out) rec.outcome = Outcome::miss_far;
  if (r.as("one_more_eval") && ran_out) ++rec.evals;  // the field evaluated once more after the loop
  return rec;
}

// A NaN or infinite ray must come back invalid (principle 8), at no more cost than a clean ray.
void invalid_input(Run& r, BadRay ray) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const MarchSettings ms = input_settings();
  const auto clean = march::march<float>(TapeField{&tape}, kCleanOrigin, kCleanDir, ms, {});
  const auto rec = march_input(r, TapeField{&tape}, ray.origin, ray.direction, ms);
  r.m["outcome"] = static_cast<double>(rec.outcome);
  r.m["evals"] = rec.evals;
  r.m["clean_ray.evals"] = clean.evals;
  r.require("invalid", rec.outcome == Outcome::invalid, "outcome " + std::string(march::to_string(rec.outcome)) + ", not invalid");
  r.require("cost", rec.evals <= 2.5 * clean.evals, "cost " + std::to_string(rec.evals) + " evaluations, over 2.5x a clean ray");
}

float denormal() { return std::numeric_limits<float>::denorm_min() * 1000; }

// Well defined: t finite, the outcome honest (no hit claimed without the threshold met), evaluations bounded.
void defined_input(Run& r, const std::string& what, const MarchSettings& ms, const std::vector<BadRay>& rays) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const TapeField field{&tape};
  int t_bad = 0, dishonest = 0, over_budget = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    BadRay ray = rays[i];
    if (r.naive() && what == "denormal") ray.direction = glm::normalize(ray.direction);  // what shaders do first
    const auto rec = march_input(r, field, ray.origin, ray.direction, ms);
    const vec3 p = ray.origin + ray.direction * rec.t;
    const bool invalid = rec.outcome == Outcome::invalid;
    t_bad += !invalid && !std::isfinite(rec.t);
    dishonest += !invalid && rec.outcome == Outcome::hit && !(field(p) < march::hit_threshold(ms, {}, rec.t));
    over_budget += rec.evals > std::max(ms.max_steps, 0);
    r.m[what + ".ray" + std::to_string(i) + ".outcome"] = static_cast<double>(rec.outcome);
    r.m[what + ".ray" + std::to_string(i) + ".evals"] = rec.evals;
  }
  r.m[what + ".wrong"] = t_bad + dishonest + over_budget;
  r.require("t_finite", t_bad == 0, what + ": " + std::to_string(t_bad) + " rays ended with a non-finite t");
  r.require("honest_hit", dishonest == 0, what + ": " + std::to_string(dishonest) + " hits claimed off the surface");
  r.require("bounded", over_budget == 0, what + ": " + std::to_string(over_budget) + " rays ran past max_steps evaluations");
}

// max_steps 0: an honest "ran out of steps" at once, no evaluation, t finite.
void max_steps_zero(Run& r, const StabilityOptions&) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  MarchSettings ms = input_settings();
  ms.max_steps = 0;
  const auto rec = march_input(r, TapeField{&tape}, kCleanOrigin, kCleanDir, ms);
  r.m["outcome"] = static_cast<double>(rec.outcome);
  r.m["evals"] = rec.evals;
  r.require("miss_steps", rec.outcome == Outcome::miss_steps, "outcome " + std::string(march::to_string(rec.outcome)));
  r.require("no_eval", rec.evals == 0, std::to_string(rec.evals) + " evaluations with max_steps 0");
  r.require("t_finite", std::isfinite(rec.t), "t not finite");
}

// eps 0 on a shallow plane: float's t stops moving once f drops under its spacing, so a loop waiting for
// f <= 0 never ends. The marcher stops at max_steps; the naive `while (f > eps)` loop runs to the budget.
void eps_zero(Run& r, const StabilityOptions&) {
  const sdf::Tape tape = sdf::compile(sdf::plane({0, 1, 0}, 0));
  const TapeField field{&tape};
  MarchSettings ms = input_settings();
  ms.hit_eps = r.as("default_eps") ? 1e-3 : 0;  // default_eps: hit_eps 0 replaced by a "sane" default
  ms.max_dist = 1e6;
  const vec3 origin(0, 1, 0), d(std::cos(0.17f), -std::sin(0.17f), 0);
  march::RayRecord<float> rec;
  if (r.naive()) {
    constexpr int kBudget = 1'000'000;  // stands in for "forever"
    float t = 0;
    for (float v = field(origin); v > 0 && rec.evals < kBudget; v = field(origin + d * t)) {
      ++rec.evals;
      t += v;
    }
    rec.outcome = rec.evals < kBudget ? Outcome::hit : Outcome::miss_steps;
    rec.t = t;
  } else {
    rec = march_input(r, field, origin, d, ms);
  }
  r.m["outcome"] = static_cast<double>(rec.outcome);
  r.m["evals"] = rec.evals;
  r.m["t"] = rec.t;
  const double t_err = std::abs(double(rec.t) - 1 / std::sin(0.17));
  r.require("bounded", rec.evals <= ms.max_steps, "ran " + std::to_string(rec.evals) + " evaluations: past max_steps (a hang)");
  r.require("t_finite", std::isfinite(rec.t), "t not finite");
  // A hit claimed with eps 0 must be where f reached 0: float spacing at t (about 6) allows 1e-5.
  r.require("hit_on_plane", rec.outcome != Outcome::hit || t_err <= 1e-5, "a hit off the plane");
}

// Like Embree's verify: a batch with bad rays costs no more than 2.5x a clean one (evaluations; seconds too).
void batch_cost(Run& r, const StabilityOptions&) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const TapeField field{&tape};
  const MarchSettings ms = input_settings();
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<BadRay> bad = {{kCleanOrigin, {nan, 0, 1}}, {kCleanOrigin, {inf, 0, 1}}, {kCleanOrigin, {0, 0, 0}},
                                   {{nan, 0, -3}, kCleanDir},   {{0, inf, -3}, kCleanDir}};
  std::vector<BadRay> clean_batch, mixed_batch;
  for (int i = 0; i < 64; ++i) {
    const BadRay ray{kCleanOrigin + vec3(0.02f * float(i % 8), 0.02f * float(i / 8), 0), kCleanDir};
    clean_batch.push_back(ray);
    mixed_batch.push_back(i % 2 ? bad[static_cast<size_t>(i / 2) % bad.size()] : ray);
  }
  const auto cost = [&](const std::vector<BadRay>& batch, double& seconds) {
    std::vector<double> times;
    long evals = 0;
    for (int rep = 0; rep < 5; ++rep) {
      evals = 0;
      const auto start = std::chrono::steady_clock::now();
      for (const BadRay& ray : batch) evals += march_input(r, field, ray.origin, ray.direction, ms).evals;
      times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    seconds = median(times);
    return static_cast<double>(evals);
  };
  double clean_s = 0, mixed_s = 0;
  const double clean = cost(clean_batch, clean_s), mixed = cost(mixed_batch, mixed_s);
  r.m["clean.evals"] = clean;
  r.m["mixed.evals"] = mixed;
  r.m["evals_ratio"] = mixed / clean;
  r.m["clean.seconds"] = clean_s;
  r.m["mixed.seconds"] = mixed_s;
  r.require("cost", mixed <= 2.5 * clean, "the batch with bad rays costs " + num(mixed / clean) + "x the clean one (limit 2.5x)");
}

// ---- meshes ----

constexpr double kMeshSampleMargin = 0.05;  // points this close to the unit sphere are left out (chord error)

std::vector<dvec3> mesh_samples(int n, double half = 1.5) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-half, half);
  std::vector<dvec3> out;
  while (static_cast<int>(out.size()) < n) {
    const dvec3 p(u(rng), u(rng), u(rng));
    if (std::abs(glm::length(p) - 1) > kMeshSampleMargin) out.push_back(p);
  }
  return out;
}

// The naive sign: the side of the nearest vertex's normal (sum of its faces' normals); defined on any mesh,
// right or not.
double naive_sign(const meshes::Mesh& mesh, dvec3 p) {
  std::vector<dvec3> normals(mesh.vertices.size(), dvec3(0));
  for (const auto& t : mesh.triangles) {
    const dvec3 n = glm::cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    for (const auto i : t) normals[i] += n;
  }
  size_t best = 0;
  for (size_t i = 1; i < mesh.vertices.size(); ++i)
    if (glm::length(mesh.vertices[i] - p) < glm::length(mesh.vertices[best] - p)) best = i;
  return glm::dot(p - mesh.vertices[best], normals[best]) < 0 ? -1 : 1;
}

// Signs at the samples against the unit sphere's: every sample signed and on the right side (a closed mesh), or
// none signed (a mesh with no inside). naive: the nearest vertex normal's side; refused_sign: no sign at all;
// sign_flipped: the winding's sign taken without the orientation.
void sphere_signs(Run& r, const meshes::Mesh& mesh, bool expect_sign) {
  const MeshReference ref(mesh);
  int wrong = 0, signed_count = 0;
  for (const dvec3& p : mesh_samples(200)) {
    std::optional<double> s = r.naive() ? std::optional<double>(naive_sign(mesh, p)) : ref.signed_distance(p);
    if (r.as("refused_sign")) s.reset();
    if (r.as("sign_flipped") && s) s = -*s;
    if (!s) continue;
    ++signed_count;
    wrong += (*s < 0) != (glm::length(p) < 1);
  }
  r.m["samples.signed"] = signed_count;
  r.m["samples.wrong_sign"] = wrong;
  if (expect_sign) {
    r.require("every_sample_signed", signed_count == 200, std::to_string(200 - signed_count) + " of 200 samples left without a sign");
    r.require("sign_right", wrong == 0, std::to_string(wrong) + " of 200 samples got the wrong side");
  } else {
    r.require("no_sample_signed", signed_count == 0, std::to_string(signed_count) + " samples given a sign by a mesh with no inside");
  }
}

// The mesh checks' report, recorded among the case's numbers.
meshes::MeshReport inspected(Run& r, const meshes::Mesh& mesh) {
  const auto rep = meshes::inspect(mesh);
  r.m["report.closed"] = rep.closed;
  r.m["report.manifold"] = rep.manifold;
  r.m["report.boundary_edges"] = rep.boundary_edges;
  r.m["report.nonmanifold_edges"] = rep.nonmanifold_edges;
  r.m["report.degenerate_faces"] = rep.degenerate_faces;
  r.m["report.duplicate_vertices"] = rep.duplicate_vertices;
  r.m["report.outward"] = rep.outward;
  return rep;
}

meshes::Mesh unit_icosphere() { return meshes::icosphere(1, 3).mesh; }

void mesh_degenerate(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  const auto a = mesh.triangles[0][0], b = mesh.triangles[0][1];
  const dvec3 mid = (mesh.vertices[a] + mesh.vertices[b]) * 0.5;
  mesh.vertices.push_back(mid);                                                     // collinear with a and b
  mesh.vertices.push_back(mid + glm::normalize(glm::cross(mid, dvec3(0, 0, 1))) * 1e-14);  // a sliver's apex
  const auto m = static_cast<std::uint32_t>(mesh.vertices.size() - 2);
  mesh.triangles.push_back({a, a, b});      // repeated index
  mesh.triangles.push_back({a, m, b});      // zero area, exactly collinear up to rounding
  mesh.triangles.push_back({a, m + 1, b});  // area 1e-14 times an edge
  const auto rep = inspected(r, mesh);
  int naive_count = 0;  // naive: only repeated indices count as degenerate
  for (const auto& t : mesh.triangles) naive_count += t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
  const int counted = r.naive() ? naive_count : rep.degenerate_faces;
  // Distances and hits on the rest stay right: within the icosphere's chord error of the sphere.
  const MeshReference ref(mesh);
  const double err = meshes::icosphere(1, 3).max_error;
  const auto distance = [&](dvec3 p) {
    if (!r.as("vertex_distance")) return ref.unsigned_distance(p);
    double d = INFINITY;  // vertex_distance: the nearest vertex taken for the nearest point
    for (const dvec3& v : mesh.vertices) d = std::min(d, glm::length(p - v));
    return d;
  };
  int bad = 0;
  for (const dvec3& p : mesh_samples(100)) bad += !(std::abs(distance(p) - std::abs(glm::length(p) - 1)) <= err + 1e-12);
  for (const dvec3& p : mesh_samples(50)) {
    const ReferenceHit h = ref.first_hit(p * 3.0, -glm::normalize(p), 10);
    bad += !(h.hit && std::isfinite(h.t) && std::abs(glm::length(h.normal) - 1) < 1e-9);
  }
  r.m["degenerate_counted"] = counted;
  r.m["queries_wrong"] = bad;
  r.require("counted", counted == 3, "counted " + std::to_string(counted) + " degenerate faces of the 3 added");
  r.require("queries", bad == 0, std::to_string(bad) + " distance or ray queries wrong or non-finite");
}

void mesh_duplicates(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  for (int i = 0; i < 5; ++i) mesh.vertices.push_back(mesh.vertices[static_cast<size_t>(i)]);
  const auto rep = inspected(r, mesh);
  const int counted = r.naive() ? 0 : rep.duplicate_vertices;  // naive: vertices compared by index, never equal
  r.m["duplicates_counted"] = counted;
  r.require("counted", counted == 5, "counted " + std::to_string(counted) + " duplicate vertices of the 5 added");
  sphere_signs(r, mesh, true);
}

// The report's numbers a variant miscounts (each a one-line slip in the mesh checks), for the cases that judge them.
meshes::MeshReport miscounted(const Run& r, meshes::MeshReport rep) {
  if (r.as("boundary_counted_twice")) rep.boundary_edges *= 2;  // once per face beside the edge
  if (r.as("fin_manifold")) {  // an edge of three faces taken for manifold (only four or more counted)
    rep.nonmanifold_edges = 0;
    rep.manifold = true;
  }
  if (r.as("volume_unsigned")) {  // the volume's absolute value: the orientation lost
    rep.signed_volume = std::abs(rep.signed_volume);
    rep.outward = true;
  }
  if (r.as("components_nonmanifold")) rep.manifold = false;  // two components read as a pinch between them
  if (r.as("outward_inverted")) rep.outward = !rep.outward;  // the volume's sign read backwards
  return rep;
}

void mesh_open(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  mesh.triangles.pop_back();
  const auto rep = miscounted(r, inspected(r, mesh));
  r.require("reports_boundary", !rep.closed && rep.boundary_edges == 3, "the hole's 3 boundary edges not reported");
  sphere_signs(r, mesh, false);
}

void mesh_nonmanifold(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  const auto a = mesh.triangles[0][0], b = mesh.triangles[0][1];
  mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]) * 1.5);  // a fin on edge a-b
  mesh.triangles.push_back({a, b, static_cast<std::uint32_t>(mesh.vertices.size() - 1)});
  const auto rep = miscounted(r, inspected(r, mesh));
  r.require("reports_nonmanifold", !rep.manifold && rep.nonmanifold_edges == 1,
            "the fin's shared edge not reported non-manifold");
  sphere_signs(r, mesh, false);
}

void mesh_inverted(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  const auto rep = miscounted(r, inspected(r, mesh));
  r.m["report.signed_volume"] = rep.signed_volume;
  r.require("reports_inward", rep.closed && rep.consistently_oriented && !rep.outward && rep.signed_volume < 0,
            "the inward orientation not reported (closed, consistent, negative volume)");
  sphere_signs(r, mesh, true);
}

// Two closed spheres 0.1 apart: points in the gap are outside both. The naive sign is read off a grid of
// 0.25 (a level set coarser than the gap), as in the sign flips users reported against OpenVDB.
void mesh_sign_flip(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh;
  for (const double x : {-1.05, 1.05}) {
    const meshes::Mesh s = unit_icosphere();
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (const dvec3& v : s.vertices) mesh.vertices.push_back(v + dvec3(x, 0, 0));
    for (auto t : s.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  const auto rep = miscounted(r, inspected(r, mesh));
  const MeshReference ref(mesh);
  const double h = 0.25;
  const auto sign_at = [&](dvec3 p) {
    if (!r.naive()) return ref.signed_distance(p);
    const dvec3 node = (glm::floor(p / h) + 0.5) * h;
    return ref.signed_distance(node);
  };
  int wrong = 0, gap_wrong = 0, samples = 0;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 300; ++i) {
    // Half the samples in the gap's slab |x| < 0.04 near the axis, half anywhere around both spheres.
    const bool gap = i % 2 == 0;
    const dvec3 p = gap ? dvec3(0.04 * u(rng), 0.3 * u(rng), 0.3 * u(rng)) : dvec3(2.2 * u(rng), 1.2 * u(rng), 1.2 * u(rng));
    const double exact = std::min(glm::length(p - dvec3(-1.05, 0, 0)), glm::length(p - dvec3(1.05, 0, 0))) - 1;
    if (std::abs(exact) < kMeshSampleMargin && !gap) continue;
    const auto s = sign_at(p);
    ++samples;
    const bool bad = !s || (*s < 0) != (exact < 0);
    wrong += bad;
    gap_wrong += bad && gap;
  }
  r.m["samples"] = samples;
  r.m["wrong_sign"] = wrong;
  r.m["gap.wrong_sign"] = gap_wrong;
  r.require("reports_closed_manifold", rep.closed && rep.manifold, "two closed spheres not reported closed and manifold");
  r.require("sign_right", wrong == 0,
            std::to_string(wrong) + " samples on the wrong side (" + std::to_string(gap_wrong) + " in the gap)");
}

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024;  // Linux reports KiB
}

// A generated sphere mesh (1.3M triangles with --full): generation, checks, tree and queries within the
// stated memory (1 KiB per triangle + 64 MiB of peak growth) and, in full runs, 60 s.
void mesh_large(Run& r, const StabilityOptions& o) {
  const int subdivisions = o.full ? 8 : 5;
  const double rss0 = peak_rss_mib();
  const auto start = std::chrono::steady_clock::now();
  meshes::ProceduralMesh pm = meshes::icosphere(1, subdivisions);
  if (r.naive()) pm.mesh.triangles.pop_back();  // a truncated build
  const auto rep = miscounted(r, meshes::inspect(pm.mesh));
  const MeshReference ref(pm.mesh);
  const double triangles = static_cast<double>(pm.mesh.triangles.size()), limit = triangles / 1024 + 64;
  std::vector<char> kept;  // scratch_kept: scratch memory kept past the limit, above anything used before
  if (r.as("scratch_kept")) kept.assign(static_cast<size_t>((rss0 + limit + 16) * 1024 * 1024), 1);
  int wrong = 0;
  for (const dvec3& p : mesh_samples(200)) {
    auto s = ref.signed_distance(p);
    if (r.as("sign_flipped") && s) s = -*s;
    wrong += !s || std::abs(*s - (glm::length(p) - 1)) > pm.max_error + 1e-12;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double growth = peak_rss_mib() - rss0;
  r.m["triangles"] = triangles;
  r.m["seconds"] = seconds;
  r.m["peak_rss_growth_mib"] = growth;
  r.m["memory_limit_mib"] = limit;
  r.m["max_error"] = pm.max_error;
  r.m["samples.wrong"] = wrong;
  r.require("closed_manifold_outward", rep.closed && rep.manifold && rep.outward,
            "the generated mesh is not closed, manifold and outward");
  r.require("chord_error", wrong == 0, std::to_string(wrong) + " of 200 signed distances off the sphere by more than the chord error");
  r.require("memory", growth <= limit, "peak memory grew " + num(growth) + " MiB, over " + num(limit));
  if (o.full) r.require("seconds", seconds <= 60, "took " + num(seconds) + " s, over 60");
}

// ---- the battery ----

std::vector<Entry> make_battery() {
  using Variants = std::vector<StabilityVariant>;
  std::vector<Entry> b;
  const auto add = [&](std::string name, std::string checks, std::string criterion, Variants variants,
                       std::function<void(Run&, const StabilityOptions&)> run) {
    b.push_back({std::move(name), std::move(checks), std::move(criterion), std::move(variants), std::move(run)});
  };
  const auto plus = [](Variants a, const Variants& more) {
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  for (int k = 1; k <= 7; ++k) {
    const double clearance = std::pow(10.0, -k);
    add("grazing.b1e-" + std::to_string(k),
        "a double ray passing 1e-" + std::to_string(k) + " above a unit sphere: steps against pi sqrt(2R/b)",
        "miss_far (never a hit: hit_eps is b/1000), steps within [0.5 law, 1.5 law + 20]",
        {{"naive", "decided", "max_steps at half the law"},
         {"eps_2b", "no_hit", "hit_eps 2b: the ray hits"},
         {"quarter_steps", "steps_law", "steps of f / 4"}},
        [clearance](Run& r, const StabilityOptions&) { grazing(r, clearance); });
  }
  for (const auto& [label, deg] : std::vector<std::pair<std::string, double>>{
           {"30deg", 30}, {"5deg", 5}, {"1deg", 1}, {"0p1deg", 0.1}, {"0p01deg", 0.01}}) {
    add("plane.incidence_" + label, "a ray at " + num(deg) + " degrees to a plane: steps against ln(eps/h0)/ln(1 - sin)",
        "hit, steps within 2 of the law, t within hit_eps / sin(theta)",
        {{"naive", "hit", "max_steps at half the law"},
         {"half_steps", "steps_law", "steps of f / 2"},
         {"hit_lifted", "t_err", "the hit lifted hit_eps off the plane along the ray"}},
        [deg = deg](Run& r, const StabilityOptions&) { incidence(r, deg); });
  }
  const Variants start_variants = {{"skip_leaving", "t_zero", "rays leaving the surface start hit_eps / 4 along"},
                                   {"inside_test_first", "one_eval", "the start evaluated for an inside test, then again"}};
  add("start.inside", "rays starting inside a sphere, both ways", "outcome inside at t = 0 after one evaluation",
      plus({{"naive", "outcome", "the shader loop: no inside outcome"}}, start_variants),
      [](Run& r, const StabilityOptions&) { start_case(r, Start::inside); });
  const Variants skip_ahead = {{"naive", "", "start hit_eps along the ray (skip-ahead)"},
                               {"inside_below_eps", "outcome", "inside when f < hit_eps instead of f < 0"}};
  add("start.on", "rays starting exactly on a sphere, both ways", "hit at t = 0 after one evaluation",
      plus(skip_ahead, start_variants), [](Run& r, const StabilityOptions&) { start_case(r, Start::on); });
  add("start.half_eps", "rays starting hit_eps/2 above a sphere, both ways", "hit at t = 0 after one evaluation",
      plus(skip_ahead, start_variants), [](Run& r, const StabilityOptions&) { start_case(r, Start::half_eps); });
  const Variants unbiased = {{"naive", "no_self_hit", "the shadow ray starts at the hit point"}};
  for (const auto& [label, bias] : std::vector<std::pair<std::string, sdf::ShadowBias>>{
           {"seed_offset", sdf::ShadowBias::seed_offset}, {"seed_ignore", sdf::ShadowBias::seed_ignore},
           {"scaled", sdf::ShadowBias::scaled}}) {
    add("shadow.self_hits." + label, "shadow rays from marched hits on a unit sphere, bias " + label,
        "no lit point's shadow ray re-hits its own surface", unbiased,
        [bias = bias](Run& r, const StabilityOptions&) { shadow_case(r, bias, 1); });
  }
  add("shadow.self_hits.scaled_far", "the scale-aware bias on a sphere of radius 1e5 (other strategies' counts beside)",
      "no self-hit with the scale-aware strategy", unbiased,
      [](Run& r, const StabilityOptions&) { shadow_case(r, sdf::ShadowBias::scaled, 1e5); });
  const Variants far_both = plus(far_variants("float"), far_variants("double"));
  add("far.camera_relative", "a unit sphere offset 1e1..1e7, marched in float camera-relative, and in double",
      "every ray hits within hit_eps / cos + 1e-5, normals within 1 degree",
      plus({{"naive", "", "float in world coordinates"}}, far_both),
      [](Run& r, const StabilityOptions&) { far_offsets(r, decade_offsets(), true); });
  add("far.embree_offset", "the scene at Embree's offset (148376, 1234, -223423), float camera-relative and double",
      "every ray hits within hit_eps / cos + 1e-5, normals within 1 degree",
      plus({{"naive", "", "float in world coordinates"}}, far_both),
      [](Run& r, const StabilityOptions&) { far_offsets(r, {{148376, 1234, -223423}}, false); });
  add("far.double", "world-coordinate double at offsets 1e1..1e7; float's error growth and breakdown beside it",
      "double: every ray within hit_eps / cos + 1e-5 and 1 degree",
      plus({{"naive", "", "float in place of double"}}, far_variants("double")), far_double);
  const Variants scale_variants = {{"naive", "", "absolute hit_eps 1e-3"},
                                   {"max_dist_short", "inner.hits", "max_dist 2 S, short of the sphere"},
                                   {"hit_lifted", "inner.t", "hits backed off 10 thresholds along the ray"},
                                   {"miss_as_hit", "outer.miss", "a ray past max_dist read as a hit"}};
  for (const auto& [label, mode] : std::vector<std::pair<std::string, march::EpsMode>>{
           {"relative", march::EpsMode::relative}, {"pixel", march::EpsMode::pixel}}) {
    for (const double s : {1e-8, 1e8})
      add("scale." + label + "." + decade(s), "a sphere of radius " + num(s) + " seen from 4x, eps_mode " + label,
          "inner rays hit within threshold / cos, outer rays miss", scale_variants,
          [mode = mode, s](Run& r, const StabilityOptions&) { scale_case(r, mode, {s}); });
    add("scale." + label + ".log_uniform", "12 sphere radii log-uniform in 1e-8..1e8 (seed 7), eps_mode " + label,
        "inner rays hit within threshold / cos, outer rays miss, at every scale", scale_variants,
        [mode = mode](Run& r, const StabilityOptions&) { scale_case(r, mode, log_uniform_scales()); });
  }
  const Variants thin_variants = {{"naive", "", "fixed steps of 0.01"},
                                  {"miss_as_hit", "agree", "a ray past max_dist read as a hit"},
                                  {"hit_lifted", "t", "hits backed off 100 hit_eps along the ray"}};
  add("thin.box_frame_1e-3", "rays across a box frame's 1e-3 edge bar", "same hit/miss as the reference, t within hit_eps / cos",
      thin_variants, [](Run& r, const StabilityOptions&) {
        thin_rays(r, sdf::make(sdf::Op::box_frame, {{"half_size", {1, 1, 1}}, {"thickness", {1e-3}}}), 1 - 2e-3,
                  1 + 1e-3, 0.3, 3.0037);
      });
  add("thin.onion_1e-4", "rays across the rim of a sphere's 1e-4 onion shell",
      "same hit/miss as the reference, t within hit_eps / cos", thin_variants, [](Run& r, const StabilityOptions&) {
        thin_rays(r, sdf::make(sdf::Op::onion, {{"thickness", {1e-4}}}, {sdf::sphere(1)}), 0.9, 1.001, 0, 3.0037);
      });
  const Variants seam_variants = {{"naive", "normal", "raw gradient normalised (eps under float spacing)"},
                                  {"one_step", "hits", "max_steps 1"},
                                  {"hit_lifted", "t", "hits backed off 10 hit_eps along the ray"}};
  add("thin.coplanar_union", "two boxes sharing a face and a coplanar top, rays down across the seam",
      "hits within hit_eps, normals +y within 1 degree, never NaN", seam_variants,
      [](Run& r, const StabilityOptions&) { coincident(r, 0); });
  add("thin.near_coincident_1e-7", "the same with one top raised 1e-7", "hits within hit_eps + 1e-7, normals +y within 1 degree",
      seam_variants, [](Run& r, const StabilityOptions&) { coincident(r, 1e-7); });
  add("thin.tiny_object", "a sphere of radius 1e-5 under hit_eps 1e-3", "flagged as under hit_eps; no hit on it unexplained",
      {{"naive", "explained", "no flag: hits taken as they come"}}, [](Run& r, const StabilityOptions&) { tiny(r); });
  const Variants feature_variants = {{"naive", "", "raw gradient normalised (eps under float spacing)"},
                                     {"unnormalised", "finite_unit", "the central difference not normalised"},
                                     {"inward_on_feature", "on_feature", "on the feature, a normal into the solid"},
                                     {"wide_eps", "off_feature", "normal_eps 0.05, wider than the gap to the feature"}};
  add("normal.box_edge", "central-difference normals on and beside a box edge",
      "finite unit; on the edge inside its faces' normal cone (within 1 degree), beside it within 1 degree of the face",
      feature_variants, [](Run& r, const StabilityOptions&) { box_normals(r, false); });
  add("normal.box_corner", "central-difference normals on and beside a box corner",
      "finite unit; on the corner inside its faces' normal cone (within 1 degree), beside it within 1 degree of the face",
      feature_variants, [](Run& r, const StabilityOptions&) { box_normals(r, true); });
  add("normal.csg_seam", "normals on and beside the seam of two united spheres",
      "finite unit; on the seam between the spheres' normals (within 1 degree), beside it within 1 degree of the nearer",
      feature_variants, seam_normals);
  const auto lip = [&](std::string name, std::string what, std::function<sdf::Scene()> scene, dvec3 lo, dvec3 hi) {
    add("lipschitz." + name, what + ": plain sphere tracing against steps f / L with the measured L",
        "plain tracing's overshoots counted (> 0), none left with the measured L",
        {{"naive", "no_overshoot", "steps f / 1"}},
        [scene = std::move(scene), lo, hi](Run& r, const StabilityOptions&) { lipschitz_case(r, scene(), lo, hi); });
  };
  lip("warp", "the warped sphere seen from above (rays cross the warp's ripples in y)", [] {
    sdf::Scene s = sdf::builtin_scene("warped");
    s.camera.position = {0, 5, 2};
    s.camera.target = {0, 0, 2};
    s.camera.up = {0, 0, 1};
    s.camera.fov_deg = 60;
    return s;
  }, {-3, -3, -1}, {3, 3, 5});
  lip("lattice_displacement", "the displaced box-frame lattice", [] { return sdf::builtin_scene("crum-lattice"); },
      {-6, -6, -6}, {6, 6, 6});
  lip("terrain", "a value-noise height field like lee-terrain's, steeper", [] {
    sdf::Scene s = sdf::builtin_scene("lee-terrain");
    s.root = sdf::make(sdf::Op::heightfield, {{"octaves", {-1.5, 1, -0.3, 3, -0.05, 6}}});
    return s;
  }, {-8, -3, -8}, {8, 3, 8});
  lip("twist", "a slab twisted at 4 radians per unit", twist_scene, {-1, -1.5, -1}, {1, 1.5, 1});
  add("mandelbulb.far", "the Mandelbulb at 1e1..1e37 from the origin (float and double), and a march from 1e5",
      "finite positive values; the march never meets a non-finite value",
      {{"naive", "far_finite", "the textbook estimator"},
       {"lipschitz_zero", "march_finite", "the march's Lipschitz constant left at 0"}},
      mandelbulb_far);
  add("mandelbulb.iterations_64", "the Mandelbulb at 64 iterations on a grid through the origin",
      "every value finite, float and double", {{"naive", "finite", "the textbook estimator"}}, mandelbulb_deep);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const auto& [label, ray] : std::vector<std::pair<std::string, BadRay>>{
           {"nan_direction", {kCleanOrigin, {nan, 0, 1}}},
           {"inf_direction", {kCleanOrigin, {inf, 0, 1}}},
           {"zero_direction", {kCleanOrigin, {0, 0, 0}}},
           {"nan_origin", {{nan, 0.2f, -3}, kCleanDir}},
           {"inf_origin", {{0.3f, -inf, -3}, kCleanDir}}}) {
    add("input." + label, "a ray with a " + label.substr(0, label.find('_')) + " " + label.substr(label.find('_') + 1),
        "outcome invalid, at most 2.5x a clean ray's evaluations",
        {{"naive", "", "the shader loop: no input guard"},
         {"invalid_as_miss", "invalid", "a bad ray rejected as a miss"},
         {"no_early_exit", "cost", "a fixed trip count: bad input flagged after every step"}},
        [ray = ray](Run& r, const StabilityOptions&) { invalid_input(r, ray); });
  }
  add("input.eps_zero", "hit_eps 0 on a shallow plane in float", "stops within max_steps; a hit only where f reached 0",
      {{"naive", "bounded", "a `while (f > eps)` loop without a step limit"},
       {"miss_at_infinity", "t_finite", "a miss reported at t = infinity"},
       {"default_eps", "hit_on_plane", "hit_eps 0 replaced by a default of 1e-3"}},
      eps_zero);
  add("input.max_steps_zero", "max_steps 0", "miss_steps after no evaluation, t finite",
      {{"naive", "", "the shader loop"},
       {"ran_out_as_miss_far", "miss_steps", "a march that ran out of steps reported as miss_far"},
       {"one_more_eval", "no_eval", "the field evaluated once more after the loop"},
       {"miss_at_infinity", "t_finite", "a miss reported at t = infinity"}},
      max_steps_zero);
  const Variants defined_variants = {{"miss_at_infinity", "t_finite", "a miss reported at t = infinity"},
                                     {"ran_out_as_hit", "honest_hit", "a march that ran out of steps read as a hit"},
                                     {"one_more_eval", "bounded", "the field evaluated once more after the loop"}};
  add("input.max_dist_inf", "max_dist infinite, rays toward and away from a sphere (and away with 50 steps)",
      "t finite (or invalid), a hit only on the surface, evaluations within max_steps",
      plus({{"naive", "", "the shader loop"}}, defined_variants), [](Run& r, const StabilityOptions&) {
        MarchSettings ms = input_settings();
        ms.max_dist = std::numeric_limits<double>::infinity();
        // The ray away doubles t each step until it overflows (invalid); with 50 steps it runs out first.
        defined_input(r, "max_dist_inf", ms, {{kCleanOrigin, kCleanDir}, {kCleanOrigin, -kCleanDir}});
        ms.max_steps = 50;
        defined_input(r, "max_dist_inf_50_steps", ms, {{kCleanOrigin, -kCleanDir}});
      });
  add("input.denormal", "denormal direction, origin and hit_eps",
      "t finite (or invalid), a hit only on the surface, evaluations within max_steps",
      plus({{"naive", "", "the shader loop, normalising the direction first"}}, defined_variants),
      [](Run& r, const StabilityOptions&) {
        MarchSettings ms = input_settings();
        defined_input(r, "denormal", ms, {{kCleanOrigin, {denormal(), 0, denormal()}}, {{denormal(), 0, -3}, kCleanDir}});
        ms.hit_eps = denormal();
        // head-on, and shallow: float's t stalls above the surface and the march runs out of steps
        defined_input(r, "denormal_eps", ms, {{kCleanOrigin, kCleanDir}, {{0, 1, -3}, glm::normalize(vec3(0, -0.01f, 1))}});
      });
  add("input.batch_cost", "64 clean rays against the same with every other ray NaN, Inf or zero",
      "the mixed batch costs at most 2.5x the clean batch's evaluations (seconds reported, not judged)",
      {{"naive", "cost", "the shader loop: no input guard"}}, batch_cost);
  const Variants signs = {{"refused_sign", "every_sample_signed", "no sign given"},
                          {"sign_flipped", "sign_right", "the winding's sign taken without the orientation"}};
  add("mesh.degenerate_triangles", "an icosphere with a repeated-index, a collinear and a sliver triangle",
      "all 3 counted degenerate; distances and ray hits right and finite",
      {{"naive", "counted", "only repeated indices counted"},
       {"vertex_distance", "queries", "the nearest vertex taken for the nearest point"}},
      mesh_degenerate);
  add("mesh.duplicate_vertices", "an icosphere with 5 vertices repeated", "all 5 counted; signs right",
      plus({{"naive", "counted", "vertices compared by index"}}, signs), mesh_duplicates);
  add("mesh.open_boundary", "an icosphere missing a triangle", "3 boundary edges reported; no sample given a sign",
      {{"naive", "no_sample_signed", "sign from the nearest vertex normal"},
       {"boundary_counted_twice", "reports_boundary", "boundary edges counted once per face beside them"}},
      mesh_open);
  add("mesh.nonmanifold_edge", "an icosphere with a fin on one edge", "1 non-manifold edge reported; no sample given a sign",
      {{"naive", "no_sample_signed", "sign from the nearest vertex normal"},
       {"fin_manifold", "reports_nonmanifold", "an edge of three faces taken for manifold"}},
      mesh_nonmanifold);
  add("mesh.inverted_orientation", "an icosphere wound inward", "reported inward (negative volume); signs still right",
      plus({{"naive", "sign_right", "sign from the nearest vertex normal"},
            {"volume_unsigned", "reports_inward", "the volume's absolute value: the orientation lost"}},
           signs),
      mesh_inverted);
  add("mesh.sign_flip_gap_0p1", "two closed spheres 0.1 apart (the OpenVDB sign-flip report)",
      "every sample's sign right, in the gap too",
      {{"naive", "sign_right", "sign read off a 0.25 grid"},
       {"components_nonmanifold", "reports_closed_manifold", "two components read as a pinch between them"}},
      mesh_sign_flip);
  add("mesh.million_triangles", "a generated icosphere: 20480 triangles, 1.3M with --full (slow)",
      "closed, manifold, outward; signed distances within the chord error; memory within 1 KiB/triangle + 64 MiB; "
      "--full: 60 s",
      {{"naive", "", "a truncated build (one triangle short)"},
       {"outward_inverted", "closed_manifold_outward", "the volume's sign read backwards"},
       {"sign_flipped", "chord_error", "the winding's sign taken without the orientation"},
       {"scratch_kept", "memory", "scratch memory kept past the limit"}},
      mesh_large);
  return b;
}

const std::vector<Entry>& battery() {
  static const std::vector<Entry> b = make_battery();
  return b;
}

}  // namespace

std::vector<std::string> stability_case_names() {
  std::vector<std::string> names;
  for (const auto& e : battery()) names.push_back(e.name);
  return names;
}

StabilityCase run_stability_case(const std::string& name, const StabilityOptions& options) {
  for (const auto& e : battery()) {
    if (e.name != name) continue;
    if (!options.variant.empty() &&
        std::none_of(e.variants.begin(), e.variants.end(), [&](const auto& v) { return v.name == options.variant; }))
      throw std::invalid_argument("stability case '" + name + "' has no variant named '" + options.variant + "'");
    StabilityCase c{e.name, e.checks, e.criterion, e.variants, {}, {}, {}, false, ""};
    Run run{c.metrics, options.variant, {}, {}, ""};
    e.run(run, options);
    for (const auto& [k, v] : c.metrics)
      if (std::isnan(v)) run.needs("numbers", false, "metric " + k + " is NaN");
    c.clauses = run.clauses;
    c.failed = run.failed;
    c.stable = run.ok();
    c.detail = run.why;
    return c;
  }
  throw std::invalid_argument("no stability case named '" + name + "'");
}

std::vector<StabilityCase> run_stability(const StabilityOptions& options) {
  std::vector<StabilityCase> out;
  for (const auto& e : battery()) out.push_back(run_stability_case(e.name, options));
  return out;
}

}  // namespace marchcheck::validation
