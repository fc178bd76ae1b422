// The checks: a scene marched as it declares, measured against the references, each metric against a limit.
#pragma once

#include "marchcheck/march/marcher.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/scene.hpp"
#include "marchcheck/validation/reference.hpp"

#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace marchcheck::validation {

struct Check {
  std::string name;   // the metric's dotted name
  double value = 0;
  double limit = 0;   // pass when value <= limit
  bool pass = false;
  std::string limit_source;  // "default" or "scene"
  std::string why;           // what the limit stands for
};

// The marched render beside the reference render (exact hits, normals and shadows; the true eye) at a reduced
// width, with the effects only marching defines (step-count and sampled occlusion, glow, bounces) left out of
// both, and their per-pixel difference.
struct ImagePair {
  march::RenderResult marched, reference;
  march::Image difference;  // one channel: the largest colour-channel difference, colours clamped to [0, 1]
};
ImagePair render_image_pair(const sdf::Scene& scene, int width, const std::vector<march::Aov>& marched_aovs = {});
// ImagePair::difference of two colour images of one size: a NaN or infinite colour of `marched` (the lee seed's
// shaded miss) is infinitely far from any.
march::Image color_difference(const march::Image& marched, const march::Image& reference);

struct SceneResult {
  std::string scene;
  std::vector<std::string> defects;
  // What judged the hits (Reference::judged_by): exact, escape-time set, certified, numerical, or parts'.
  std::string reference;
  std::map<std::string, double> metrics;
  std::vector<Check> checks;
  std::vector<std::string> not_checked;  // metrics with a default limit this scene's kind is not held to
  // Per metric, the ray or point that counted against it first (or, for a largest value, the one that has it),
  // with its numbers: where to start looking when the check fails.
  std::map<std::string, std::string> offenders;
  std::optional<ImagePair> images;  // with ValidateOptions::keep_images
  bool pass() const;
};

// The table the command line prints: each check's value, limit, result and whose limit it is, and under each
// failed check the ray that counted against it first.
void print_checks(const SceneResult& result, std::ostream& out);

// A metric by name, NaN when the result does not have it (a check that did not apply).
double metric_value(const std::map<std::string, double>& metrics, const std::string& name);

struct ValidateOptions {
  int rays_x = 64, rays_y = 36;  // primary rays sampled across the image
  int image_width = 320;         // width of the marched/reference image pair (0: no image comparison)
  double image_threshold = 0.1;  // a pixel "differs" when a channel differs by more than this
  bool keep_images = false;      // keep the image pair (marched with the steps AOV) in the result
};

// The image positions (pixels, x then y) of the primary rays validate samples, row by row: the rays a subject's
// march is asked for, through the scene's camera.
std::vector<glm::dvec2> sampled_pixels(const sdf::Scene& scene, const ValidateOptions& options);

// The reference as the renderer's oracle (for reference renders); ref must outlive it.
march::SurfaceOracle oracle_of(const Reference& ref);

SceneResult validate_scene(const sdf::Scene& scene, const ValidateOptions& options = {});

// One ray's march as the judge sees it.
struct MarchedRay {
  march::Outcome outcome = march::Outcome::invalid;  // hit, miss_far, miss_steps (ran out of steps), inside, invalid
  double t = 0;   // where the march ended, in units of |direction|
  int evals = 0;  // field evaluations it made
  std::optional<glm::dvec3> normal;  // at a hit: the marcher's own normal, when it computes one
  // The consumer learns the outcome from the distance alone (a miss as 0, which a hit at the ray origin also
  // returns; an unfinished ray as the t it stopped at): DESIGN's "no sentinel values".
  bool sentinel = false;
  bool decided() const { return march::decided(outcome); }

  static MarchedRay hit(double t, std::optional<glm::dvec3> normal = std::nullopt) {
    return {march::Outcome::hit, t, 0, normal};
  }
  static MarchedRay miss(double t) { return {march::Outcome::miss_far, t, 0, std::nullopt}; }
  static MarchedRay out_of_steps(double t) { return {march::Outcome::miss_steps, t, 0, std::nullopt}; }
};

// What validate judges, as callables: a field, how it marches a ray, its normals and shadows, and what it
// declares. validate_scene judges a scene's own (its compiled tape, marcher and estimators); a user's field and
// marcher are judged the same way, against the references of the scene that says what they should draw.
struct Subject {
  std::function<double(glm::dvec3)> field;  // for the field's own checks (Lipschitz constant, bound)
  // The field in the march's own arithmetic, for the bound where the march relies on it (beside the surface);
  // empty: judged in double only.
  std::function<double(glm::dvec3)> marched_field;
  std::function<MarchedRay(glm::dvec3 origin, glm::dvec3 direction)> march;
  // The normal at a marched hit p (t along the ray); empty: the marcher's own (MarchedRay::normal) or none.
  std::function<glm::dvec3(glm::dvec3 p, double t)> normal;
  // Visibility in [0, 1] from hit p (normal n, t along the eye ray) toward a light; empty: no shadow judged.
  std::function<double(glm::dvec3 p, glm::dvec3 n, glm::dvec3 to_light, double light_dist, double t,
                       const sdf::Light& light)>
      visibility;
  sdf::FieldInfo declared;     // the kind and Lipschitz bound the field claims
  bool exact_outside = false;  // the field promises the true distance outside its solid (hits within hit_eps)
  double unit_roundoff = 0;    // of the march's arithmetic: how far rounding may move a hit point, per unit
  // What the march measures positions from (march::march_origin): its rounding grows with |p - origin|.
  glm::dvec3 origin{0};
  // The marcher stops where |f| < the threshold, inside the solid too (a user's marcher, as tutorials write it; a
  // hit refined by HitRefine::secant): a hit no farther past the surface than the threshold is a hit, not a step
  // through it.
  bool stops_either_side = false;
};

// The scene's own subject: its compiled tape, marched as the scene declares (marcher, limits, precision, and a
// miss read as distance 0 where the scene says its consumer does so), with its normal estimator and shadows. What
// validate_scene judges, and what every study of the scene marches.
Subject scene_subject(const sdf::Scene& scene);

// The checks of validate_scene on a subject, against the references of scene (its intended tree, else its root),
// marched through its camera with its march settings (hit threshold, limits, step rule) and lights. No image
// comparison: that needs the scene's renderer.
SceneResult validate_subject(const sdf::Scene& scene, const Subject& subject, const ValidateOptions& options = {});

// The default limits and what each stands for; a scene's `limits` replace them by name.
struct DefaultLimit {
  const char* metric;
  double limit;
  const char* why;
  // An estimate's boundary turns within the normal stencil and within a pixel: its normals and image are
  // reported against the set's, and checked only where the scene sets a limit.
  bool checks_estimates = true;
};
const std::vector<DefaultLimit>& default_limits();
// The result's checks: each default limit whose metric it has, or the scene's own limit by that name; a metric
// passes at its limit. An estimate is held only to the limits that check estimates, unless the scene sets one:
// the others go to not_checked.
void apply_limits(const std::map<std::string, double>& scene_limits, bool estimate, SceneResult& result);
// Why a metric is in SceneResult::not_checked, as the command line and the report say it.
inline constexpr const char* kNotCheckedWhy =
    "an estimate: the set's boundary turns within the normal stencil and the pixel; a scene limit checks it";

}  // namespace marchcheck::validation
