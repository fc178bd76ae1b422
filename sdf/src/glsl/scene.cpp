// The scene around a GLSL file given alone (`marchcheck validate my.glsl`): its field, and a camera framing the
// region where the field is negative, found by sampling.
#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/scene_file.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <numbers>
#include <optional>
#include <sstream>
#include <vector>

namespace marchcheck::sdf {

namespace {

// The box of the grid points (48 per side) where f < 0, in the first of [-2, 2]^3, [-8, 8]^3, ... [-512, 512]^3
// that has some and is not negative everywhere; empty when none has.
std::optional<Box3> negative_region(const GlslField& field) {
  constexpr int kSide = 48;
  for (double half = 2; half <= 512; half *= 4) {
    Box3 box{glm::dvec3(INFINITY), glm::dvec3(-INFINITY)};
    int negative = 0;
    const double cell = 2 * half / (kSide - 1);
    for (int i = 0; i < kSide; ++i)
      for (int j = 0; j < kSide; ++j)
        for (int k = 0; k < kSide; ++k) {
          const glm::dvec3 p = glm::dvec3(-half) + glm::dvec3(i, j, k) * cell;
          if (!(field.distance(p) < 0)) continue;
          ++negative;
          box.lo = glm::min(box.lo, p - cell);
          box.hi = glm::max(box.hi, p + cell);
        }
    if (negative > 0 && negative < kSide * kSide * kSide) return box;
  }
  return std::nullopt;
}

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

// The shader's limits applied to the scene, as the description says them.
std::string apply_shader_limits(Scene& scene, const std::string& text, const std::string& path) {
  std::ostringstream said;
  said << "limits from the shader:";
  bool any = false;
  for (const Limit& limit : shader_limits())
    for (const char* name : limit.names)
      if (const std::optional<double> v = glsl_constant(text, path, name)) {
        std::ostringstream value;
        value << std::setprecision(17) << *v;
        apply_setting(scene, limit.setting, value.str());
        said << " " << name << " = " << *v << " (" << limit.setting << ")";
        any = true;
        break;
      }
  if (!any) said << " none (MAX_STEPS, MAX_DIST, SURF_DIST): marchcheck's defaults";
  return said.str();
}

}  // namespace

std::optional<double> glsl_constant(const std::string& text, const std::string& file, const std::string& name) {
  GlslSpec spec;
  spec.function = "marchcheck_constant";
  spec.measured = false;
  try {
    const GlslField probe(spec, text + "\nfloat marchcheck_constant(vec3 p) { return float(" + name + "); }\n", file);
    return probe.distance(glm::dvec3(0));
  } catch (const GlslError&) {
    return std::nullopt;  // no such name (the source's own errors surface when it is compiled for real)
  }
}

Scene glsl_scene(const std::string& path, const std::string& function) {
  const std::optional<std::string> text = read_text_file(path);
  if (!text) throw SceneError(path + ": cannot read the GLSL file");
  GlslSpec spec;
  spec.function = function;
  return glsl_scene(path, spec, *text);
}

Scene glsl_scene(const std::string& path, GlslSpec spec, const std::string& text) {
  const std::string function = spec.function;
  spec.source = std::filesystem::absolute(path).lexically_normal().string();
  Scene s;
  s.name = std::filesystem::path(path).stem().string();
  // A result's .y = 0 to 7 colours the surface (materials y0 to y7), as a shader's own material ids would; the
  // shader's own list, where its spec has one, stands.
  if (spec.materials.empty()) {
    const glm::dvec3 palette[] = {{0.8, 0.8, 0.8}, {0.85, 0.35, 0.25}, {0.3, 0.55, 0.85}, {0.35, 0.7, 0.35},
                                  {0.9, 0.75, 0.3}, {0.6, 0.4, 0.75}, {0.3, 0.75, 0.75}, {0.75, 0.5, 0.35}};
    for (int k = 0; k < 8; ++k) {
      s.materials.push_back({"y" + std::to_string(k), palette[k]});
      spec.materials.push_back(k);
    }
  }
  s.root = make(Op::glsl);
  s.root.glsl = std::make_shared<const GlslField>(spec, text, path);
  s.root.source = spec.source;
  const std::optional<Box3> region = negative_region(*s.root.glsl);
  if (!region) throw SceneError(path + ": " + function + " is nowhere negative in [-512, 512]^3: no surface to frame");
  // Looking at the region's centre from above and in front, at a distance that fits its bounding sphere in the
  // vertical field of view with a margin.
  const double radius = 0.5 * glm::length(region->size());
  s.camera.target = region->center();
  s.camera.position = region->center() + glm::normalize(glm::dvec3(0.6, 0.5, 1)) *
                                             (1.3 * radius / std::tan(s.camera.fov_deg * std::numbers::pi / 360));
  s.march.max_dist = 4 * glm::length(s.camera.position - s.camera.target) + 2 * radius;
  const std::string limits = apply_shader_limits(s, text, path);
  // Steps of f / L with the measured constant: a field of unknown kind is not trusted to be 1-Lipschitz.
  s.march.marcher = Marcher::scaled;
  Light light;
  light.direction = glm::normalize(glm::dvec3(-0.4, -1, -0.3));
  light.shadow = ShadowMode::hard;
  s.lights.push_back(light);
  std::ostringstream about;
  about << "GLSL field " << function << " of " << path << "; camera framing the region where it is negative, ["
        << region->lo.x << ", " << region->hi.x << "] x [" << region->lo.y << ", " << region->hi.y << "] x ["
        << region->lo.z << ", " << region->hi.z << "], found by sampling (override with --set camera.*); .y = 0 to 7 "
        << "picks materials y0 to y7; " << limits;
  s.description = about.str();
  return s;
}

}  // namespace marchcheck::sdf
