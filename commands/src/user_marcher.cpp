#include "user_marcher.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/scene_file.hpp"

#include <array>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

namespace marchcheck::commands {

namespace {

// What a shader calls its marcher's limits, most common spelling first.
struct Limit {
  const char* setting;  // the scene's march setting it becomes
  std::vector<const char*> names;
};
const std::vector<Limit>& shader_limits() {
  static const std::vector<Limit> limits = {
      {"max_steps", {"MAX_STEPS", "MAX_STEP", "MAX_MARCHING_STEPS", "MAX_ITERATIONS", "STEPS"}},
      {"max_dist", {"MAX_DIST", "MAX_DISTANCE", "FAR", "MAX_T"}},
      {"hit_eps", {"SURF_DIST", "SURFACE_DIST", "EPSILON", "MIN_DIST", "EPS"}}};
  return limits;
}

using RayKey = std::array<double, 6>;

}  // namespace

sdf::Scene user_marcher_scene(const std::string& path, const gpu::UserMarcher& marcher, std::string& about) {
  sdf::Scene scene = sdf::glsl_scene(path, marcher.map);
  const std::string text = *sdf::read_text_file(path);  // glsl_scene has read it
  std::ostringstream said;
  said << "limits from the shader:";
  bool any = false;
  for (const Limit& limit : shader_limits())
    for (const char* name : limit.names)
      if (const std::optional<double> v = gpu::glsl_constant(text, path, name)) {
        std::ostringstream value;
        value << std::setprecision(17) << *v;
        sdf::apply_setting(scene, limit.setting, value.str());
        said << " " << name << " = " << *v << " (" << limit.setting << ")";
        any = true;
        break;
      }
  if (!any) said << " none found (MAX_STEPS, MAX_DIST, SURF_DIST): the scene's defaults";
  about = said.str();
  sdf::apply_setting(scene, "precision", "float");
  // What march.safe_step_ratio assumes of the user's marcher: steps of f, as tutorials write it.
  sdf::apply_setting(scene, "marcher", "sphere");
  return scene;
}

validation::SceneResult judge_user_marcher(const sdf::Scene& scene, const gpu::UserMarcher& marcher,
                                            std::string& renderer, const validation::ValidateOptions& options) {
  const march::Camera camera(scene.camera, scene.width, scene.height);
  const std::vector<glm::dvec2> pixels = validation::sampled_pixels(scene, options);
  std::vector<std::pair<glm::dvec3, glm::dvec3>> rays;
  for (const glm::dvec2 pixel : pixels) {
    const march::Ray ray = camera.ray(pixel.x, pixel.y);
    rays.push_back({ray.origin, glm::normalize(ray.direction)});
  }
  const sdf::GlslField& field = *scene.root.glsl;
  const std::string text = *sdf::read_text_file(field.spec().source);
  const gpu::UserMarch marched =
      gpu::march_on_driver(text, field.spec().source, marcher, field.spec().uniforms, rays);
  renderer = marched.renderer;
  // Each ray's march as the judge asks for it (by origin and direction, in units of the direction's length).
  std::map<RayKey, validation::MarchedRay> by_ray;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const march::Ray ray = camera.ray(pixels[i].x, pixels[i].y);
    const gpu::UserRay& r = marched.rays[i];
    const double len = glm::length(ray.direction);
    validation::MarchedRay m;
    m.t = r.t / len;
    m.evals = r.map_calls;
    m.normal = r.normal;
    const glm::dvec3 end = ray.origin + glm::normalize(ray.direction) * r.t;
    // The shader draws a surface wherever t stops short of its far distance; one that stopped because its steps ran
    // out, still away from the surface, is undecided.
    if (!std::isfinite(r.t) || r.t >= scene.march.max_dist)
      m.outcome = march::Outcome::miss_far;
    else if (r.map_calls >= scene.march.max_steps && std::abs(field.distance(end)) > scene.march.hit_eps)
      m.outcome = march::Outcome::miss_steps;
    else
      m.outcome = march::Outcome::hit;
    by_ray[{ray.origin.x, ray.origin.y, ray.origin.z, ray.direction.x, ray.direction.y, ray.direction.z}] = m;
  }
  validation::Subject subject;
  subject.field = [&field](glm::dvec3 p) { return field.distance(p); };
  subject.march = [&by_ray](glm::dvec3 o, glm::dvec3 d) {
    return by_ray.at({o.x, o.y, o.z, d.x, d.y, d.z});
  };
  subject.declared = sdf::derive_info(scene.root, scene.time);
  subject.exact_outside = subject.declared.kind == sdf::Kind::exact;
  subject.unit_roundoff = 0x1p-24;  // the driver's float
  subject.stops_either_side = true;  // |f| < SURF_DIST, as tutorials write the test; f < eps stops anywhere inside
  validation::SceneResult result = validation::validate_subject(scene, subject, options);
  result.scene += " (marcher " + marcher.march + " on the GL driver)";
  return result;
}

}  // namespace marchcheck::commands
