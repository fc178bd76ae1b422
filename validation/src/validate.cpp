#include "marchcheck/validation/validate.hpp"

#include "marchcheck/march/camera_relative.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/effects.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/march/tolerances.hpp"
#include "marchcheck/sdf/interval.hpp"
#include "marchcheck/validation/certified.hpp"
#include "marchcheck/validation/reference.hpp"
#include "marchcheck/validation/statistics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <iomanip>
#include <memory>
#include <optional>
#include <random>
#include <sstream>

namespace marchcheck::validation {

using glm::dvec3;
using march::Outcome;

double metric_value(const std::map<std::string, double>& metrics, const std::string& name) {
  const auto it = metrics.find(name);
  return it == metrics.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
}

bool SceneResult::pass() const {
  return std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.pass; });
}

const std::vector<DefaultLimit>& default_limits() {
  static const std::vector<DefaultLimit> limits = {
      {"hit.false_hit", 0, "rays marched to a hit where the reference has no surface near (outside the grazing band)"},
      {"hit.false_miss", 0, "rays marched to a miss through a surface the reference hits"},
      {"hit.overshoot", 0, "hits beyond the reference's first surface: the march stepped through it"},
      {"hit.undecided", 0.002, "fraction of rays that ran out of steps (neither hit nor miss)"},
      {"hit.surface_dist_over_eps", 1.05, "hit point's distance to the surface over the hit threshold there"},
      {"normal.angle_p99_deg", 2, "99th percentile of the normal's angle error at agreed hits", false},
      {"shadow.false_shadow", 0.002, "fraction of lit reference points the marched shadow darkens (acne)"},
      {"shadow.false_lit", 0.002, "fraction of shadowed reference points the marched shadow lights (leaks)"},
      {"march.over_max_steps", 0, "rays whose march evaluated the field more often than max_steps allows"},
      {"march.sentinel_t", 0,
       "fraction of rays whose outcome reaches the consumer only as a distance (a miss as 0, which a hit at the ray "
       "origin also returns, or as +inf; an unfinished ray as where it stopped)"},
      {"normal.length_err_max", 1e-4, "largest | |n| - 1 | of the normals at hits (float rounding gives ~1e-7)"},
      {"sdf.lipschitz_over_declared", 1.001, "measured Lipschitz constant over the declared one"},
      {"march.safe_step_ratio", 1.001, "measured Lipschitz constant times the marcher's step per unit of f"},
      {"sdf.overestimate_max", 1e-6, "largest |f|/L minus the true distance's upper bound (> 0: not a bound)"},
      {"sdf.overestimate_marched_max", 1e-6,
       "the same for the field in the march's arithmetic beside the surface, past that arithmetic's rounding of the "
       "point (16 unit roundoffs of 1 + |p|, p measured as the march measures it)"},
      {"sdf.precision_gap_max", 0,
       "largest |f in the march's arithmetic - f in double| at the visible surface points, past that arithmetic's "
       "rounding of the point (16 unit roundoffs of 1 + |p| times the declared Lipschitz constant): a field that is "
       "another function in the march's precision (a height field's height difference, float against double)"},
      {"image.pixels_over", 0.02, "fraction of pixels whose colour differs from the reference render by > 0.1",
       false},
      {"image.nan_pixels", 0,
       "fraction of pixels whose marched colour is NaN or infinite (a driver writes them as it likes: black on "
       "llvmpipe)"},
      {"camera.fov_err_deg", 1e-6, "field of view the rays span minus the declared one"},
      {"camera.ray_norm_err", 1e-6, "largest | |direction| - 1 | of the generated rays"},
      {"sdf.lipschitz_certified_over_declared", 1.001,
       "Lipschitz constant proven by interval arithmetic along the primary rays, over the declared one (above 1: "
       "the declared one is not proven, or proven understated)"},
      {"reference.undecidable", 0.01,
       "fraction of rays the certified reference cannot decide at its width (left out of the hit checks)"},
  };
  return limits;
}

namespace {

// Exact fields, and unions and rigid motions of them, give the true distance outside the solid.
bool is_exact_outside(const sdf::Node& n, double time) {
  if (sdf::derive_info(n, time).kind == sdf::Kind::exact) return true;
  switch (n.op) {
    case sdf::Op::union_:
    case sdf::Op::translate:
    case sdf::Op::rotate:
    case sdf::Op::scale:
      return std::all_of(n.children.begin(), n.children.end(), [&](const sdf::Node& c) { return is_exact_outside(c, time); });
    default: return false;
  }
}

// The scene's own field, marcher and estimators in arithmetic T.
template <class T>
Subject subject_in(const sdf::Scene& scene) {
  using V = glm::vec<3, T>;
  // Points and ray origins come in world coordinates; the march measures them from origin (in double).
  const dvec3 origin = march::march_origin(scene);
  const auto tape = std::make_shared<const sdf::Tape>(march::march_tape(scene, origin));
  const auto ctx = std::make_shared<const march::MarchContext>(
      march::march_context(march::Camera(scene.camera, scene.width, scene.height), scene, origin));
  const march::TapeField field{tape.get()};
  const sdf::MarchSettings settings = scene.march;
  Subject s;
  s.field = [tape, origin](dvec3 p) { return sdf::evaluate(*tape, p - origin); };
  s.marched_field = [tape, origin](dvec3 p) { return static_cast<double>(sdf::evaluate(*tape, V(p - origin))); };
  s.march = [tape, ctx, field, settings, origin](dvec3 o, dvec3 d) {
    const auto r = march::march<T>(field, V(o - origin), V(d), settings, *ctx);
    const auto read = march::as_read(r, settings);  // as the seed's consumer reads it
    MarchedRay m{read.outcome, static_cast<double>(read.t), r.evals, std::nullopt};
    // Its outcome known only from a sentinel distance: a miss returned as 0, an unfinished ray as where it stopped.
    m.sentinel = settings.reading != sdf::RecordReading::outcome && r.outcome != Outcome::hit;
    return m;
  };
  s.normal = [tape, field, settings, origin](dvec3 p, double t) {
    const T eps = T(settings.normal_eps_scaled ? settings.normal_eps * t : settings.normal_eps);
    return dvec3(march::estimate_normal(field, V(p - origin), settings.normal, eps).n);
  };
  s.visibility = [tape, ctx, field, settings, origin](dvec3 p, dvec3 n, dvec3 to_light, double dist, double t,
                                                      const sdf::Light& light) {
    return static_cast<double>(march::shadow_visibility<T>(field, V(p - origin), V(n), V(to_light), static_cast<T>(dist),
                                                           static_cast<T>(t), light, settings, *ctx)
                                   .visibility);
  };
  s.declared = sdf::derive_info(scene.root, scene.time);
  s.exact_outside = is_exact_outside(scene.root, scene.time);
  s.unit_roundoff = std::numeric_limits<T>::epsilon();
  // A hit refined by a secant step lands on the surface to O(eps^2), on either side of it.
  s.stops_either_side = scene.march.refine == sdf::HitRefine::secant;
  s.origin = origin;
  return s;
}

std::string vec_text(dvec3 v) {
  std::ostringstream out;
  out << std::setprecision(6) << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return out.str();
}

// One primary ray with what the march and the reference said of it, as an offender is named.
std::string ray_text(double px, double py, const march::Ray& ray, const MarchedRay& rec, const ReferenceHit& rh) {
  std::ostringstream out;
  out << std::setprecision(6) << "ray through pixel (" << px << ", " << py << "), origin " << vec_text(ray.origin)
      << ", direction " << vec_text(ray.direction) << ": marched " << march::to_string(rec.outcome) << " at t = "
      << rec.t << " after " << rec.evals << " evaluations; reference "
      << (rh.hit ? "hit at t = " : "miss") ;
  if (rh.hit) out << rh.t;
  return out.str();
}

// The first offender of each counted metric, and the worst of each largest value. text() is called only for the
// offender kept, so rays that change nothing cost no formatting.
struct Offenders {
  std::map<std::string, std::pair<double, std::string>> by_metric;
  template <class Text>
  void first(const std::string& metric, const Text& text) {
    if (!by_metric.count(metric)) by_metric[metric] = {0.0, "first: " + text()};
  }
  template <class Text>
  void largest(const std::string& metric, double value, const Text& text) {
    const auto it = by_metric.find(metric);
    if (it == by_metric.end() || value > it->second.first) by_metric[metric] = {value, "worst: " + text()};
  }
};

// The scene's intended tree, else its root stepped by the subject's declared constant where the numerical root
// finder judges it.
Reference reference_for(const sdf::Scene& s, const Subject& subject) {
  return s.intended ? Reference(*s.intended, s.time) : Reference(s.root, s.time, subject.declared.lipschitz);
}

// What the judges of one scene share: the subject, the reference (the scene's intended tree, else its root),
// the camera and its march context, and the first offender of each metric.
struct Judging {
  const sdf::Scene& scene;
  const Subject& subject;
  const Reference ref;
  const march::Camera camera;
  const march::MarchContext ctx;
  // An estimate promises no distance, so its hits are judged by what the image can show: the set within the
  // pixel's footprint.
  const bool estimate;
  const double max_dist;
  const double declared;  // the Lipschitz constant the field declares
  Offenders offenders;

  Judging(const sdf::Scene& s, const Subject& subj)
      : scene(s), subject(subj), ref(reference_for(s, subj)), camera(s.camera, s.width, s.height),
        ctx(march::march_context(camera, subj.declared.lipschitz)), estimate(subj.declared.kind == sdf::Kind::estimate),
        max_dist(std::isfinite(s.march.max_dist) ? s.march.max_dist : 1e6), declared(subj.declared.lipschitz) {}

  double hit_threshold(double t) const { return static_cast<double>(march::hit_threshold<double>(scene.march, ctx, t)); }
};

// One primary ray: what the subject marched and what the reference found along it.
struct SampledRay {
  double px, py;
  march::Ray ray;
  double len;  // of the ray's direction (the marcher's t is in its units)
  dvec3 dn;    // the unit direction
  MarchedRay rec;
  ReferenceHit rh;
  std::string text() const { return ray_text(px, py, ray, rec, rh); }
};

SampledRay sample_ray(const Judging& j, double px, double py) {
  SampledRay r{px, py, j.camera.ray(px, py), 0, {}, {}, {}};
  r.len = glm::length(r.ray.direction);
  r.dn = r.ray.direction / r.len;
  r.rec = j.subject.march(r.ray.origin, r.ray.direction);
  r.rh = j.ref.first_hit(r.ray.origin, r.dn, j.max_dist);
  return r;
}

// Two unit vectors across the direction d.
std::pair<dvec3, dvec3> across(dvec3 d) {
  const dvec3 side = glm::normalize(glm::cross(d, std::abs(d.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0)));
  return {side, glm::cross(side, d)};
}

// A marched hit on the surface the reference hits, close enough to compare its t, normal and shadows.
struct AgreedHit {
  dvec3 p_m;                 // the marched hit point
  std::optional<dvec3> n_m;  // its normal, when the subject gives one
  double t_m;                // its distance along the unit ray
  double eps_m;              // the hit threshold there
  bool at_edge;              // the reference surface turns sharply at this pixel
};

// Normal errors at agreed hits, away from edges and at sharp edges, and normals' lengths at every hit.
struct NormalJudge {
  bool judged;  // the subject gives normals (its own estimator, or the marcher's)
  std::vector<double> angle, edge_angle;
  double length_err = 0;

  explicit NormalJudge(bool estimator) : judged(estimator) {}

  void length(Offenders& offenders, const SampledRay& r, dvec3 n) {
    judged = true;
    const double err = std::abs(glm::length(n) - 1);
    length_err = std::max(length_err, err);
    offenders.largest("normal.length_err_max", err, [&] { return r.text() + "; normal " + vec_text(n); });
  }
  void angle_to_reference(Offenders& offenders, const SampledRay& r, dvec3 n, bool at_edge) {
    const double a = std::acos(std::clamp(glm::dot(n, r.rh.normal), -1.0, 1.0)) * 180 / std::numbers::pi;
    (at_edge ? edge_angle : angle).push_back(a);
    offenders.largest(at_edge ? "normal.edge_angle_p99_deg" : "normal.angle_p99_deg", a, [&] {
      return r.text() + "; normal " + vec_text(n) + ", reference normal " + vec_text(r.rh.normal);
    });
  }
  void report(std::map<std::string, double>& m) const {
    if (judged) {
      m["normal.angle_max_deg"] = angle.empty() ? 0 : *std::max_element(angle.begin(), angle.end());
      m["normal.angle_p99_deg"] = percentile(angle, 0.99);
      double mean = 0;
      for (double a : angle) mean += a / static_cast<double>(angle.size());
      m["normal.angle_mean_deg"] = mean;
      m["normal.length_err_max"] = length_err;
    }
    if (!edge_angle.empty()) {
      m["normal.edge_samples"] = static_cast<double>(edge_angle.size());
      m["normal.edge_angle_max_deg"] = *std::max_element(edge_angle.begin(), edge_angle.end());
      m["normal.edge_angle_p99_deg"] = percentile(edge_angle, 0.99);
    }
  }
};

// Each primary ray's outcome against the reference: false hits and misses, steps through the surface, rays
// undecided or over the step limit, and how far agreed hits lie from the surface.
struct HitJudge {
  int rays = 0, false_hit = 0, false_miss = 0, overshoot = 0, undecided = 0, ambiguous = 0, over_steps = 0;
  int sentinel = 0;
  int uncertified = 0, numerical_disagree = 0;  // the certified reference's undecidable rays; the cross-check's
  double ray_norm_err = 0, surface_over_eps = 0, surface_dist_max = 0, evals = 0;
  std::vector<double> t_err;

  // The ray's verdict; an agreed hit when the marched one can be compared with the reference's.
  std::optional<AgreedHit> judge(Judging& j, const SampledRay& r, NormalJudge& normals) {
    ray_norm_err = std::max(ray_norm_err, std::abs(r.len - 1));
    evals += r.rec.evals;
    ++rays;
    const auto text = [&] { return r.text(); };
    if (r.rec.evals > j.scene.march.max_steps) {
      ++over_steps;
      j.offenders.first("march.over_max_steps", text);
    }
    if (r.rec.sentinel) {
      ++sentinel;
      j.offenders.first("march.sentinel_t", text);
    }
    cross_check(j, r);
    if (r.rh.undecided) {
      ++uncertified;
      j.offenders.first("reference.undecidable", text);
    }
    if (r.rh.inside || r.rh.unknown || r.rh.undecided) return std::nullopt;
    bool at_edge = false;
    const double band = grazing_band(j, r);
    if (grazing(j, r, band, at_edge)) {
      ++ambiguous;
      return std::nullopt;
    }
    if (r.rec.outcome == Outcome::miss_steps) {
      ++undecided;
      j.offenders.first("hit.undecided", text);
    }
    if (r.rec.outcome == Outcome::hit) return judge_hit(j, r, normals, band, at_edge);
    if (r.rec.outcome == Outcome::miss_far && r.rh.hit && r.rh.t < j.max_dist * 0.999) {
      ++false_miss;
      j.offenders.first("hit.false_miss", text);
    }
    return std::nullopt;
  }

  // The numerical reference (steps of f / L) on the rays the certified one decides: where the two differ, in
  // verdict or in t beyond both bounds, the numerical one trusted a wrong L (or a step jumped a thin feature).
  void cross_check(Judging& j, const SampledRay& r) {
    if (j.ref.kind() != ReferenceKind::certified || r.rh.undecided) return;
    const ReferenceHit n = j.ref.numerical_first_hit(r.ray.origin, r.dn, j.max_dist);
    const bool differ = n.hit != r.rh.hit || n.inside != r.rh.inside ||
                        (n.hit && std::abs(n.t - r.rh.t) > j.ref.t_error_bound(r.rh.t) + march::tolerance::kReferenceBisection);
    if (!differ) return;
    ++numerical_disagree;
    j.offenders.first("reference.numerical_disagree", [&] {
      return r.text() + "; numerical reference " + (n.hit ? "hit at t = " + std::to_string(n.t) : std::string("no hit"));
    });
  }

  // Rays whose neighbours a grazing band away disagree with them are left out.
  static double grazing_band(const Judging& j, const SampledRay& r) {
    const double t_scale = r.rh.hit ? r.rh.t : std::min(j.max_dist, 10.0);
    return march::tolerance::grazing_band(j.hit_threshold(t_scale), t_scale);
  }
  static bool grazing(const Judging& j, const SampledRay& r, double band, bool& at_edge) {
    const auto [side, up] = across(r.dn);
    bool grazing = false;
    for (const dvec3 offset : {side, -side, up, -up}) {
      const ReferenceHit neighbour = j.ref.first_hit(r.ray.origin + offset * band, r.dn, j.max_dist);
      grazing = grazing || neighbour.hit != r.rh.hit;
      at_edge = at_edge ||
                (neighbour.hit && r.rh.hit && glm::dot(neighbour.normal, r.rh.normal) < march::tolerance::kSharpEdgeCos);
    }
    return grazing;
  }

  std::optional<AgreedHit> judge_hit(Judging& j, const SampledRay& r, NormalJudge& normals, double band,
                                     bool at_edge) {
    const auto text = [&] { return r.text(); };
    const ReferenceHit& rh = r.rh;
    const double t_m = r.rec.t * r.len;
    const double eps_m = j.hit_threshold(r.rec.t);
    if (!std::isfinite(t_m)) {  // a hit at an infinite distance (a miss shaded as the lee seed does) has no point
      ++false_hit;
      j.offenders.first("hit.false_hit", text);
      return std::nullopt;
    }
    const dvec3 p_m = r.ray.origin + r.ray.direction * r.rec.t;
    const std::optional<dvec3> n_m = j.subject.normal ? j.subject.normal(p_m, r.rec.t) : r.rec.normal;
    if (n_m) normals.length(j.offenders, r, *n_m);
    // An upper bound on the hit point's distance to the true surface: the ray's own, then the probes
    // (the reference normal's reverse and the marched one's: exact where the surface is flat).
    NearestSurface near{rh.hit ? std::abs(rh.t - t_m) : INFINITY, t_m < rh.t ? r.dn : -r.dn};
    probe_nearest(j.ref, p_m, {rh.hit ? -rh.normal : dvec3(0), n_m ? -*n_m : dvec3(0)}, near);
    double upper = near.distance;
    // Rounding of the hit point itself is allowed on top of the threshold.
    const double rounding =
        march::tolerance::hit_point_rounding(j.subject.unit_roundoff, r.ray.origin - j.subject.origin, t_m);
    const double allowed = eps_m * r.len + rounding + j.ref.t_error_bound(rh.t);
    // Within the solid but no farther past the first surface than the hit point's float rounding: rounded
    // across the surface (t's own ulp at t = 100 is 8e-6), not a step through it. A marcher that stops on either
    // side is judged by its depth across the surface (flat at this scale), as a hit outside by its distance.
    const bool just_past = near.inside && rh.hit &&
                           (std::abs(t_m - rh.t) <= rounding + j.ref.t_error_bound(rh.t) || j.subject.stops_either_side);
    if (near.inside && !just_past) upper = 0;  // deeper in the solid: the surface distance is unknown, the hit is wrong
    if (just_past && j.subject.stops_either_side)
      upper = std::min(upper, std::abs(t_m - rh.t) * std::abs(glm::dot(r.dn, rh.normal)));
    if ((near.inside && !just_past) || (rh.hit && t_m > rh.t + band && upper > allowed)) {
      ++overshoot;  // the march went through the first surface
      j.offenders.first("hit.overshoot", text);
      return std::nullopt;
    }
    const double footprint = j.ctx.footprint_at_0 + j.ctx.footprint_slope * r.rec.t;
    if (upper > std::max(2 * allowed + band, j.estimate ? footprint : 0.0) &&
        !in_shell(j, p_m, near.toward, upper, eps_m)) {
      ++false_hit;  // nothing the reference knows is near the marched hit
      j.offenders.first("hit.false_hit", text);
      return std::nullopt;
    }
    surface_dist_max = std::max(surface_dist_max, upper);
    // Only a field exact outside its solid promises hits within the threshold: a bound may stop farther.
    if (j.subject.exact_outside) {
      surface_over_eps = std::max(surface_over_eps, upper / (allowed + 1e-300));
      j.offenders.largest("hit.surface_dist_over_eps", upper / (allowed + 1e-300), text);
    }
    // A legitimate near-hit on a surface the ray itself passes by: nothing to compare t or the normal with.
    // The ray's own gap to the reference hit beyond 10x the nearest surface's distance means it meets the
    // surface there at more than 84 degrees from its normal, or not at this point at all.
    if (!rh.hit || std::abs(rh.t - t_m) > 10 * (upper + allowed) + band) return std::nullopt;
    t_err.push_back(std::abs(t_m - rh.t));
    return AgreedHit{p_m, n_m, t_m, eps_m, at_edge};
  }

  // A bound may be below the threshold farther from the surface than the threshold (where its gradient is
  // small): such a hit is honest when |f| stays below the threshold on the straight way to the nearest surface
  // point (a field whose own solid covers the gap is negative there: a wrong surface, still caught). Samples
  // eps / L apart, all below eps: |f| < 1.5 eps on the whole way.
  static bool in_shell(const Judging& j, dvec3 p_m, dvec3 toward, double upper, double eps_m) {
    if (j.subject.exact_outside || !std::isfinite(upper)) return false;
    const int n = static_cast<int>(std::min(4096.0, std::ceil(upper * j.declared / eps_m))) + 1;
    for (int s = 0; s <= n; ++s)
      if (std::abs(j.subject.field(p_m + toward * (upper * s / n))) >= eps_m) return false;
    return true;
  }

  void report(const Judging& j, std::map<std::string, double>& m) const {
    m["hit.rays"] = rays;
    m["hit.grazing_excluded"] = ambiguous;
    m["hit.false_hit"] = false_hit;
    m["hit.false_miss"] = false_miss;
    m["hit.overshoot"] = overshoot;
    m["hit.undecided"] = rays > 0 ? static_cast<double>(undecided) / rays : 0;
    m["hit.t_err_max"] = t_err.empty() ? 0 : *std::max_element(t_err.begin(), t_err.end());
    m["hit.t_err_p99"] = percentile(t_err, 0.99);
    m["hit.surface_dist_max"] = surface_dist_max;
    if (j.subject.exact_outside) m["hit.surface_dist_over_eps"] = surface_over_eps;
    m["march.over_max_steps"] = over_steps;
    m["march.sentinel_t"] = rays > 0 ? static_cast<double>(sentinel) / rays : 0;
    m["camera.ray_norm_err"] = ray_norm_err;
    m["cost.march_evals_per_ray"] = rays > 0 ? evals / rays : 0;
    if (j.ref.kind() == ReferenceKind::certified) {
      m["reference.undecidable"] = rays > 0 ? static_cast<double>(uncertified) / rays : 0;
      m["reference.numerical_disagree"] = numerical_disagree;
    }
  }
};

// The subject's shadows at agreed hits against the reference's, away from shadow edges.
struct ShadowJudge {
  int samples = 0, false_shadow = 0, false_lit = 0;

  void judge(Judging& j, const SampledRay& r, const AgreedHit& h) {
    const dvec3 p_r = r.ray.origin + r.dn * r.rh.t;
    for (size_t l = 0; l < j.scene.lights.size(); ++l) {
      const sdf::Light& light = j.scene.lights[l];
      if (light.shadow == sdf::ShadowMode::none) continue;
      const dvec3 lp = light.position_at(j.scene.time);
      const bool point = light.type == sdf::LightType::point;
      const dvec3 to_light = point ? glm::normalize(lp - p_r) : -glm::normalize(light.direction);
      const double dist = point ? glm::length(lp - p_r) : j.max_dist;
      if (glm::dot(to_light, r.rh.normal) < 0.05) continue;  // at or past the terminator: self-shadowed either way
      const dvec3 start = p_r + r.rh.normal * march::tolerance::shadow_lift(p_r - j.subject.origin);
      const bool lit = !j.ref.first_hit(start, to_light, dist).hit;
      const double edge_band = march::tolerance::shadow_edge_band(h.eps_m * r.len, dist);
      if (shadow_edge(j, start, to_light, r.rh.normal, dist, edge_band, lit)) continue;
      ++samples;
      const double v = j.subject.visibility(h.p_m, h.n_m.value_or(r.rh.normal), to_light,
                                            point ? glm::length(lp - h.p_m) : INFINITY, r.rec.t, light);
      const auto text = [&] {
        std::ostringstream out;
        out << r.text() << "; light " << l << ": visibility " << v << " where the reference is "
            << (lit ? "lit" : "shadowed");
        return out.str();
      };
      if (lit && v < 0.5) {
        ++false_shadow;
        j.offenders.first("shadow.false_shadow", text);
      }
      if (!lit && v >= 0.5) {
        ++false_lit;
        j.offenders.first("shadow.false_lit", text);
      }
    }
  }

  // Shadow edges: points whose shadow ray, moved by band, changes its verdict.
  static bool shadow_edge(const Judging& j, dvec3 start, dvec3 to_light, dvec3 normal, double dist, double band,
                          bool lit) {
    const auto [side, up] = across(to_light);
    bool edge = false;
    for (const dvec3 offset : {side, -side, up, -up})
      // Lifted along the normal as far as it moves sideways, so the start never sinks into the surface.
      edge = edge || (!j.ref.first_hit(start + (offset + normal) * band, to_light, dist).hit) != lit;
    return edge;
  }

  void report(std::map<std::string, double>& m) const {
    if (samples == 0) return;
    m["shadow.samples"] = samples;
    m["shadow.false_shadow"] = static_cast<double>(false_shadow) / samples;
    m["shadow.false_lit"] = static_cast<double>(false_lit) / samples;
  }
};

// The field against its declaration, near the surfaces the camera sees (reference hits, and their distance
// along the ray): Lipschitz by finite differences in double; boundedness against the reference distance's upper
// bound (the nearest surface along 26 directions), only where that reference is exact.
void judge_field(Judging& j, const std::vector<std::pair<dvec3, double>>& surface_points, double ray_norm_err,
                 std::map<std::string, double>& m) {
  std::mt19937 rng(1234);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0, 1);
  const auto field = [&j](dvec3 p) { return j.subject.field(p); };
  double lipschitz = 0, overestimate = -INFINITY, marched_overestimate = -INFINITY, estimate_ratio = 0;
  // How far the march's arithmetic may move p by rounding it: 16 unit roundoffs of its coordinates' magnitude.
  const auto rounding_of = [&j](dvec3 p) { return 16 * j.subject.unit_roundoff * (1 + glm::length(p - j.subject.origin)); };
  // The field against the reference's upper bound of the distance at p (f = field(p)), only where that reference is
  // exact; and in the march's arithmetic, past its rounding of p. The gradient's step: 1e-6 of the sample's scale.
  const auto bound_at = [&](dvec3 p, double f, double scale) {
    if (!(j.ref.exact() || j.estimate)) return;
    // Down the field's own gradient lies the nearest point of a field close to the reference's.
    const dvec3 grad = march::central_normal(field, p, 1e-6 * scale).n;
    NearestSurface near;
    probe_nearest(j.ref, p, {f > 0 ? -grad : grad}, near);
    if (near.inside || !std::isfinite(near.distance)) return;  // the upper bound needs a point outside
    if (j.estimate) {
      estimate_ratio = std::max(estimate_ratio, f / near.distance);
      return;
    }
    const double over = std::abs(f) / j.declared - near.distance;
    overestimate = std::max(overestimate, over);
    const auto text = [&](const char* what, double value) {
      std::ostringstream out;
      out << std::setprecision(6) << "at " << vec_text(p) << ": " << what << " = " << value << ", a surface "
          << near.distance << " away along " << vec_text(near.toward);
      return out.str();
    };
    j.offenders.largest("sdf.overestimate_max", over, [&] { return text("f", f); });
    if (!j.subject.marched_field) return;
    const double fm = j.subject.marched_field(p);
    const double over_m = std::abs(fm) / j.declared - near.distance - rounding_of(p);
    marched_overestimate = std::max(marched_overestimate, over_m);
    j.offenders.largest("sdf.overestimate_marched_max", over_m, [&] { return text("f in the march's arithmetic", fm); });
  };
  double precision_gap = -INFINITY;
  const size_t stride = std::max<size_t>(1, surface_points.size() / 300);
  for (size_t k = 0; k < surface_points.size(); k += stride) {
    const auto [p0, t0] = surface_points[k];
    if (j.subject.marched_field) {
      const double gap = std::abs(j.subject.marched_field(p0) - field(p0)) - rounding_of(p0) * std::max(1.0, j.declared);
      precision_gap = std::max(precision_gap, gap);
      j.offenders.largest("sdf.precision_gap_max", gap, [&] {
        std::ostringstream out;
        out << std::setprecision(6) << "at " << vec_text(p0) << ": f in the march's arithmetic "
            << j.subject.marched_field(p0) << ", in double " << field(p0);
        return out.str();
      });
    }
    const double scale = 0.05 * (1 + t0);
    for (int rep = 0; rep < 8; ++rep) {
      const dvec3 p = p0 + glm::normalize(dvec3(g(rng), g(rng), g(rng))) * (scale * u(rng));
      const dvec3 dir = glm::normalize(dvec3(g(rng), g(rng), g(rng)));
      // Any two points bound L from below: close pairs see steep slopes, wider ones see jumps (a shape crossing
      // its repetition cell) that a close pair almost never straddles.
      const double f = field(p);
      for (const double h : {1e-5 * scale, 1e-2 * scale, 0.3 * scale}) {
        const double slope = std::abs(field(p + dir * h) - f) / h;
        lipschitz = std::max(lipschitz, slope);
        j.offenders.largest("sdf.lipschitz_over_declared", slope, [&] {
          std::ostringstream out;
          out << std::setprecision(6) << "slope " << slope << " from " << vec_text(p) << " along " << vec_text(dir)
              << " over " << h;
          return out.str();
        });
      }
      if (rep < 2) bound_at(p, f, scale);
    }
    // Beside the surface, where a march takes its last steps: 10^-4 to 10^-1 of the scale, so a field wrong only
    // near its surface (a mesh's float distance over a sliver once was, by 8.7x) is seen there.
    for (int rep = 0; rep < 2; ++rep) {
      const double radius = scale * std::pow(10.0, -1 - 3 * u(rng));
      const dvec3 p = p0 + glm::normalize(dvec3(g(rng), g(rng), g(rng))) * radius;
      bound_at(p, field(p), radius);
    }
  }
  m["sdf.lipschitz_measured"] = lipschitz;
  if (std::isfinite(precision_gap)) m["sdf.precision_gap_max"] = precision_gap;
  if (j.estimate) {
    // Nothing declared to contradict: how far the estimate exceeds the distance to the set is reported.
    m["sdf.estimate_over_distance_max"] = estimate_ratio;
    return;
  }
  m["sdf.lipschitz_declared"] = j.declared;
  m["sdf.lipschitz_over_declared"] = lipschitz / j.declared;
  // How far one step can reach past the surface: step = f * scale along a direction of length |d|, and f may
  // change by L per unit; above 1 a step can cross the surface. (The relaxed marcher's fallback is its own
  // guard: its base step counts.)
  const auto& s = j.scene.march;
  const double per_unit = s.marcher == sdf::Marcher::fixed ? 0 : sdf::step_per_unit_f(s, j.declared);
  m["march.safe_step_ratio"] = lipschitz * per_unit * (1 + ray_norm_err);
  if (std::isfinite(overestimate)) m["sdf.overestimate_max"] = overestimate;
  if (std::isfinite(marched_overestimate)) m["sdf.overestimate_marched_max"] = marched_overestimate;
}

}  // namespace

std::vector<glm::dvec2> sampled_pixels(const sdf::Scene& scene, const ValidateOptions& options) {
  std::vector<glm::dvec2> out;
  for (int y = 0; y < options.rays_y; ++y)
    for (int x = 0; x < options.rays_x; ++x)
      out.push_back({(x + 0.5) * scene.width / options.rays_x, (y + 0.5) * scene.height / options.rays_y});
  return out;
}

namespace {

// The declared Lipschitz constant proven, or shown understated, along every eighth primary ray to its
// reference hit (or max_dist), for fields the certified reference judges.
void certify_field(Judging& j, const std::vector<RayPath>& paths, std::map<std::string, double>& m) {
  if (j.ref.kind() != ReferenceKind::certified || paths.empty() || j.estimate) return;
  const sdf::Tape tape = sdf::compile(j.scene.root, j.scene.time);
  if (!sdf::interval_supported(tape)) return;
  std::vector<RayPath> sample;
  for (size_t i = 0; i < paths.size(); i += 8) sample.push_back(paths[i]);
  const double target = kLipschitzTolerance * j.declared;
  const CertifiedLipschitz c = certify_lipschitz(tape, sample, target);
  m["sdf.lipschitz_certified"] = c.upper;
  m["sdf.lipschitz_proven_lower"] = c.lower;
  m["sdf.lipschitz_certified_over_declared"] = c.upper / j.declared;
  m["sdf.lipschitz_certified_boxes"] = c.boxes;
  if (c.upper <= target) return;
  std::ostringstream out;
  out << std::setprecision(6);
  if (c.lower > j.declared) {
    out << "understated: the slope is at least " << c.lower << " near " << vec_text(c.lower_at);
  } else {
    out << "not proven: the bound stays " << c.upper << " over a piece " << c.steepest_length << " long at "
        << vec_text(c.steepest) << " (" << c.unproven << " such pieces)";
  }
  j.offenders.first("sdf.lipschitz_certified_over_declared", [&] { return out.str(); });
}

// Every judge over the scene's grid of primary rays.
void measure(const sdf::Scene& scene, const Subject& subject, const ValidateOptions& opt,
             std::map<std::string, double>& m, std::map<std::string, std::string>& offender_text,
             std::string& reference) {
  Judging j(scene, subject);
  HitJudge hits;
  NormalJudge normals(static_cast<bool>(subject.normal));  // else judged when the marcher gives a normal
  ShadowJudge shadows;
  std::vector<std::pair<dvec3, double>> surface_points;  // reference hits and their distance, for the field
  std::vector<RayPath> paths;  // every decided ray's way to its reference hit, or to max_dist
  for (const glm::dvec2 pixel : sampled_pixels(scene, opt)) {
    const SampledRay r = sample_ray(j, pixel.x, pixel.y);
    if (!r.rh.undecided && !r.rh.unknown && !r.rh.inside) paths.push_back({r.ray.origin, r.dn, r.rh.hit ? r.rh.t : j.max_dist});
    const std::optional<AgreedHit> agreed = hits.judge(j, r, normals);
    if (!agreed) continue;
    if (agreed->n_m) normals.angle_to_reference(j.offenders, r, *agreed->n_m, agreed->at_edge);
    surface_points.push_back({r.ray.origin + r.dn * r.rh.t, r.rh.t});
    if (subject.visibility) shadows.judge(j, r, *agreed);
  }
  hits.report(j, m);
  normals.report(m);
  shadows.report(m);
  if (scene.camera.model == sdf::CameraModel::pinhole || scene.camera.model == sdf::CameraModel::frustum)
    m["camera.fov_err_deg"] = std::abs(j.camera.measured_vertical_fov_deg() - scene.camera.fov_deg);
  judge_field(j, surface_points, hits.ray_norm_err, m);
  certify_field(j, paths, m);
  reference = j.ref.judged_by();
  for (const auto& [metric, offender] : j.offenders.by_metric) offender_text[metric] = offender.second;
  offender_text["march.safe_step_ratio"] = offender_text["sdf.lipschitz_over_declared"];
}

void image_metrics(const ImagePair& pair, double threshold, std::map<std::string, double>& m) {
  double sum2 = 0, worst = 0;
  size_t over = 0;
  const auto& marched = pair.marched.color.pixels;
  const auto& reference = pair.reference.color.pixels;
  const size_t pixels = pair.difference.pixels.size();
  for (size_t i = 0; i < 3 * pixels; ++i) {
    const double d = std::clamp<double>(marched[i], 0, 1) - std::clamp<double>(reference[i], 0, 1);
    sum2 += d * d;
  }
  for (const float d : pair.difference.pixels) {
    worst = std::max<double>(worst, d);
    if (d > threshold) ++over;
  }
  size_t undefined = 0;
  for (size_t i = 0; i < pixels; ++i)
    undefined += !std::isfinite(marched[3 * i]) || !std::isfinite(marched[3 * i + 1]) || !std::isfinite(marched[3 * i + 2]);
  m["image.nan_pixels"] = static_cast<double>(undefined) / static_cast<double>(pixels);
  const double rms = std::sqrt(sum2 / static_cast<double>(3 * pixels));
  m["image.rms"] = rms;
  m["image.max"] = worst;
  m["image.psnr"] = rms > 0 ? 20 * std::log10(1 / rms) : 99;
  m["image.pixels_over"] = static_cast<double>(over) / static_cast<double>(pixels);
}

}  // namespace

ImagePair render_image_pair(const sdf::Scene& scene, int width, const std::vector<march::Aov>& marched_aovs) {
  sdf::Scene small = sdf::scaled_to_width(scene, std::min(width, scene.width));
  small.effects.ao = sdf::AmbientOcclusion::none;
  small.effects.glow = 0;
  small.effects.max_bounces = 0;
  const Reference ref(scene.intended ? *scene.intended : scene.root, scene.time);
  const march::SurfaceOracle oracle = oracle_of(ref);
  ImagePair pair{march::render(small, marched_aovs), march::render(small, {}, &oracle), {}};
  pair.difference = color_difference(pair.marched.color, pair.reference.color);
  return pair;
}

march::Image color_difference(const march::Image& marched, const march::Image& reference) {
  march::Image difference(marched.width, marched.height, 1);
  for (size_t i = 0; i < difference.pixels.size(); ++i) {
    float worst = 0;
    for (size_t c = 0; c < 3; ++c) {
      const float m = marched.pixels[3 * i + c];
      if (!std::isfinite(m)) worst = std::numeric_limits<float>::infinity();
      worst = std::max(worst, std::abs(std::clamp(m, 0.f, 1.f) - std::clamp(reference.pixels[3 * i + c], 0.f, 1.f)));
    }
    difference.pixels[i] = worst;
  }
  return difference;
}

march::SurfaceOracle oracle_of(const Reference& ref) {
  return {[&ref](dvec3 o, dvec3 d, double t_max) -> std::optional<march::SurfaceOracle::Hit> {
    const ReferenceHit h = ref.first_hit(o, d, t_max);
    if (!h.hit) return std::nullopt;
    return march::SurfaceOracle::Hit{h.t, h.normal, ref.t_error_bound(h.t)};
  }};
}

void apply_limits(const std::map<std::string, double>& scene_limits, bool estimate, SceneResult& r) {
  for (const auto& d : default_limits()) {
    auto value = r.metrics.find(d.metric);
    if (value == r.metrics.end()) continue;  // not applicable to this scene
    auto own = scene_limits.find(d.metric);
    if (estimate && !d.checks_estimates && own == scene_limits.end()) {
      r.not_checked.push_back(d.metric);
      continue;
    }
    Check c;
    c.name = d.metric;
    c.value = value->second;
    c.why = d.why;
    c.limit = own != scene_limits.end() ? own->second : d.limit;
    c.limit_source = own != scene_limits.end() ? "scene" : "default";
    c.pass = c.value <= c.limit;
    r.checks.push_back(c);
  }
}

namespace {

SceneResult judge(const sdf::Scene& scene, const Subject& subject, const ValidateOptions& options, bool images) {
  const auto start = std::chrono::steady_clock::now();
  SceneResult r;
  r.scene = scene.name;
  r.defects = scene.defects;
  measure(scene, subject, options, r.metrics, r.offenders, r.reference);
  if (images && options.image_width > 0) {
    ImagePair pair = render_image_pair(scene, options.image_width,
                                       options.keep_images ? std::vector{march::Aov::steps} : std::vector<march::Aov>{});
    image_metrics(pair, options.image_threshold, r.metrics);
    if (options.keep_images) r.images = std::move(pair);
  }
  r.metrics["cost.seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  apply_limits(scene.limits, subject.declared.kind == sdf::Kind::estimate, r);
  return r;
}

}  // namespace

SceneResult validate_scene(const sdf::Scene& scene, const ValidateOptions& options) {
  return judge(scene, scene_subject(scene), options, true);
}

Subject scene_subject(const sdf::Scene& scene) {
  return scene.march.precision == sdf::Precision::float64 ? subject_in<double>(scene) : subject_in<float>(scene);
}

SceneResult validate_subject(const sdf::Scene& scene, const Subject& subject, const ValidateOptions& options) {
  return judge(scene, subject, options, false);
}

void print_checks(const SceneResult& r, std::ostream& out) {
  out << r.scene << (r.defects.empty() ? "" : "  (reproduces a seed defect)") << ": " << (r.pass() ? "PASS" : "FAIL")
      << "  (reference: " << r.reference << ")\n";
  out << "  " << std::left << std::setw(30) << "check" << std::right << std::setw(13) << "value" << std::setw(13)
      << "limit" << "  result  limit from\n";
  for (const auto& c : r.checks) {
    out << "  " << std::left << std::setw(30) << c.name << std::right << std::setw(13) << std::setprecision(4)
        << std::defaultfloat << c.value << std::setw(13) << c.limit << "  " << (c.pass ? "pass  " : "FAIL  ") << "  "
        << c.limit_source << "\n";
    const auto offender = r.offenders.find(c.name);
    if (!c.pass && offender != r.offenders.end()) out << "      " << offender->second << "\n";
  }
  if (r.not_checked.empty()) return;
  out << "  reported, not checked (" << kNotCheckedWhy << "):";
  for (const auto& name : r.not_checked) out << " " << name << " = " << std::setprecision(4) << metric_value(r.metrics, name);
  out << "\n";
}

}  // namespace marchcheck::validation
