#include "user_marcher.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/half.hpp"
#include "marchcheck/sdf/scene_file.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>

namespace marchcheck::commands {

namespace {

using RayKey = std::array<double, 6>;

// Floats between a and b (0: the same float).
double ulps_between(float a, float b) {
  const auto ordered = [](float x) {
    std::int32_t i;
    std::memcpy(&i, &x, sizeof i);
    return i < 0 ? std::int64_t{INT32_MIN} - i : std::int64_t{i};
  };
  return static_cast<double>(std::llabs(ordered(a) - ordered(b)));
}

// The same marcher on the driver and on the CPU (float, double, and half: mediump): rays whose outcome (t short of
// the far distance or not) differs, t's largest difference where both stop short (float's ulps; relative, for
// half), and rays the CPU's evaluator could not finish.
struct CpuMarches {
  std::vector<double> in_float, in_double, in_half;
};
void driver_against_cpu(const sdf::Scene& scene, const gpu::UserMarch& driver, const CpuMarches& cpu,
                        std::map<std::string, double>& m) {
  const auto hit = [&](double t) { return t < scene.march.max_dist; };
  double differs = 0, double_differs = 0, half_differs = 0, ulps = 0, half_relative = 0, unfinished = 0;
  for (std::size_t i = 0; i < driver.rays.size(); ++i) {
    const double t = driver.rays[i].t;
    const double in_float = cpu.in_float[i], in_double = cpu.in_double[i], in_half = cpu.in_half[i];
    if (std::isnan(in_float) || std::isnan(in_double) || std::isnan(in_half)) {
      ++unfinished;
      continue;
    }
    differs += hit(t) != hit(in_float);
    double_differs += hit(in_float) != hit(in_double);
    half_differs += hit(in_float) != hit(in_half);
    if (hit(in_float) && hit(in_half) && in_float > 0)
      half_relative = std::max(half_relative, std::abs(in_half - in_float) / in_float);
    if (hit(t) && hit(in_float))
      ulps = std::max(ulps, ulps_between(static_cast<float>(t), static_cast<float>(in_float)));
  }
  m["driver.outcome_differs"] = differs;
  m["driver.t_ulps_max"] = ulps;
  m["driver.cpu_unfinished"] = unfinished;
  m["cpu.float_double_outcome_differs"] = double_differs;
  m["cpu.float_half_outcome_differs"] = half_differs;
  m["cpu.float_half_t_rel_max"] = half_relative;
}

}  // namespace

sdf::Scene user_marcher_scene(const UserShader& shader, const gpu::UserMarcher& marcher) {
  sdf::GlslSpec spec;
  spec.function = marcher.map;
  spec.uniforms = shader.uniforms;
  sdf::Scene scene = sdf::glsl_scene(shader.path, spec, shader.text);
  sdf::apply_setting(scene, "precision", "float");
  // What march.safe_step_ratio assumes of the user's marcher: steps of f, as tutorials write it.
  sdf::apply_setting(scene, "marcher", "sphere");
  return scene;
}

validation::SceneResult judge_user_marcher(const sdf::Scene& scene, const UserShader& shader,
                                            const gpu::UserMarcher& marcher, std::string& renderer,
                                            const validation::ValidateOptions& options) {
  const march::Camera camera(scene.camera, scene.width, scene.height);
  const std::vector<glm::dvec2> pixels = validation::sampled_pixels(scene, options);
  std::vector<std::pair<glm::dvec3, glm::dvec3>> rays;
  for (const glm::dvec2 pixel : pixels) {
    const march::Ray ray = camera.ray(pixel.x, pixel.y);
    rays.push_back({ray.origin, glm::normalize(ray.direction)});
  }
  const sdf::GlslField& field = *scene.root.glsl;
  const gpu::UserMarch marched = gpu::march_on_driver(shader.text, shader.path, marcher, shader.uniforms, rays);
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
  driver_against_cpu(scene, marched,
                     {gpu::march_on_cpu<float>(shader.text, shader.path, marcher, shader.uniforms, rays),
                      gpu::march_on_cpu<double>(shader.text, shader.path, marcher, shader.uniforms, rays),
                      gpu::march_on_cpu<sdf::Half>(shader.text, shader.path, marcher, shader.uniforms, rays)},
                     result.metrics);
  result.scene += " (marcher " + marcher.march + " on the GL driver)";
  return result;
}

void set_shader_parameter(UserShader& shader, const std::string& name, const std::string& value) {
  // A #define is a line of its own (GLSL's preprocessor directives are): "#  define NAME ...".
  std::istringstream in(shader.text);
  std::string line, text;
  bool defined = false;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string hash, directive, word;
    words >> hash;
    if (hash == "#") words >> directive;
    else if (hash.size() > 1 && hash[0] == '#') directive = hash.substr(1);
    words >> word;
    if (!hash.empty() && hash[0] == '#' && directive == "define" && word == name) {
      line = "#define " + name + " " + value;
      defined = true;
    }
    text += line + "\n";
  }
  if (defined) {
    shader.text = text;
    return;
  }
  if (!sdf::glsl_declares_uniform(shader.text, shader.path, name))
    throw sdf::SceneError(shader.path + ": --vary glsl." + name + ": the shader has no #define " + name +
                          " and no uniform " + name);
  double number = 0;
  std::istringstream parse(value);
  if (!(parse >> number) || !parse.eof())
    throw sdf::SceneError("--vary glsl." + name + "=" + value + ": a uniform's value is a number");
  shader.uniforms[name] = {number};
}

}  // namespace marchcheck::commands
