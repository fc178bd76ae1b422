// Thin features, coincident surfaces and an object smaller than hit_eps.
#include "battery.hpp"

#include "marchcheck/march/normals.hpp"
#include "marchcheck/validation/reference.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace marchcheck::validation::stability {

namespace {

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
    t_off += !(err <= ms.hit_eps / std::max(-glm::dot(d, exact.normal), 0.05) + ref.t_error_bound(exact.t) + 1e-6);
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

}  // namespace

void add_thin_cases(Battery& b) {
  const Variants thin_variants = {{"naive", "", "fixed steps of 0.01"},
                                  {"miss_as_hit", "agree", "a ray past max_dist read as a hit"},
                                  {"hit_lifted", "t", "hits backed off 100 hit_eps along the ray"}};
  b.add("thin.box_frame_1e-3", "rays across a box frame's 1e-3 edge bar",
        "same hit/miss as the reference, t within hit_eps / cos", thin_variants, [](Run& r, const StabilityOptions&) {
          thin_rays(r, sdf::make(sdf::Op::box_frame, {{"half_size", {1, 1, 1}}, {"thickness", {1e-3}}}), 1 - 2e-3,
                    1 + 1e-3, 0.3, 3.0037);
        });
  b.add("thin.onion_1e-4", "rays across the rim of a sphere's 1e-4 onion shell",
        "same hit/miss as the reference, t within hit_eps / cos", thin_variants, [](Run& r, const StabilityOptions&) {
          thin_rays(r, sdf::make(sdf::Op::onion, {{"thickness", {1e-4}}}, {sdf::sphere(1)}), 0.9, 1.001, 0, 3.0037);
        });
  const Variants seam_variants = {{"naive", "normal", "raw gradient normalised (eps under float spacing)"},
                                  {"one_step", "hits", "max_steps 1"},
                                  {"hit_lifted", "t", "hits backed off 10 hit_eps along the ray"}};
  b.add("thin.coplanar_union", "two boxes sharing a face and a coplanar top, rays down across the seam",
        "hits within hit_eps, normals +y within 1 degree, never NaN", seam_variants,
        [](Run& r, const StabilityOptions&) { coincident(r, 0); });
  b.add("thin.near_coincident_1e-7", "the same with one top raised 1e-7",
        "hits within hit_eps + 1e-7, normals +y within 1 degree", seam_variants,
        [](Run& r, const StabilityOptions&) { coincident(r, 1e-7); });
  b.add("thin.tiny_object", "a sphere of radius 1e-5 under hit_eps 1e-3",
        "flagged as under hit_eps; no hit on it unexplained",
        {{"naive", "explained", "no flag: hits taken as they come"}}, [](Run& r, const StabilityOptions&) { tiny(r); });
}

}  // namespace marchcheck::validation::stability
