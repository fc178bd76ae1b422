// The checks: a scene marched as it declares, measured against the references, each metric against a limit.
#pragma once

#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/scene.hpp"
#include "marchcheck/validation/reference.hpp"

#include <map>
#include <optional>
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

struct SceneResult {
  std::string scene;
  std::vector<std::string> defects;
  std::map<std::string, double> metrics;
  std::vector<Check> checks;
  std::vector<std::string> not_checked;  // metrics with a default limit this scene's kind is not held to
  std::optional<ImagePair> images;  // with ValidateOptions::keep_images
  bool pass() const;
};

// A metric by name, NaN when the result does not have it (a check that did not apply).
double metric_value(const std::map<std::string, double>& metrics, const std::string& name);

struct ValidateOptions {
  int rays_x = 64, rays_y = 36;  // primary rays sampled across the image
  int image_width = 320;         // width of the marched/reference image pair (0: no image comparison)
  double image_threshold = 0.1;  // a pixel "differs" when a channel differs by more than this
  bool keep_images = false;      // keep the image pair (marched with the steps AOV) in the result
};

// The reference as the renderer's oracle (for reference renders); ref must outlive it.
march::SurfaceOracle oracle_of(const Reference& ref);

SceneResult validate_scene(const sdf::Scene& scene, const ValidateOptions& options = {});

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
// Why a metric is in SceneResult::not_checked, as the command line and the report say it.
inline constexpr const char* kNotCheckedWhy =
    "an estimate: the set's boundary turns within the normal stencil and the pixel; a scene limit checks it";

}  // namespace marchcheck::validation
