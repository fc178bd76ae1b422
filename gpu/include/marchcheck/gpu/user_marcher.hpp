// A user's own GLSL ray marcher (and normal function) run on the GL driver for marchcheck's rays, its field's
// calls counted per ray; and a GLSL field evaluated on the driver at given points.
#pragma once

#include "marchcheck/gpu/driver.hpp"

#include <glm/vec3.hpp>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace marchcheck::gpu {

// The user's functions, by name. The marcher is `R NAME(vec3 ro, vec3 rd)` for a unit rd, R one of float, vec2,
// vec3, vec4 (t is its .x), or a struct whose member holding t is named: "NAME.member". The normal function is
// `vec3 NAME(vec3 p)`. The field (the function the marcher calls) is `R map(vec3 p)` by default.
struct UserMarcher {
  std::string march = "rayMarch";
  std::string normal;  // empty: none
  std::string map = "map";
};

struct UserRay {
  double t = 0;        // what the marcher returned: distance along the unit direction
  int map_calls = 0;   // the field's calls while the marcher ran (not the normal's)
  std::optional<glm::dvec3> normal;  // at ro + rd t, when the marcher has a normal function
};

struct UserMarch {
  std::vector<UserRay> rays;
  std::string renderer;
  double seconds = 0;
};

// The source's marcher for each ray (origin, unit direction), on the driver. Throws sdf::GlslError for a source
// that does not compile or lacks a function (file:line), DriverUnavailable, DriverError.
UserMarch march_on_driver(const std::string& text, const std::string& file, const UserMarcher& marcher,
                          const std::map<std::string, std::vector<double>>& uniforms,
                          const std::vector<std::pair<glm::dvec3, glm::dvec3>>& rays, double seconds_limit = 60);

// The same marcher for the same rays on the CPU, by marchcheck's evaluator of the source's SPIR-V, in float (as
// IEEE computes it: what the driver should match), double, or sdf::Half (binary16: GLSL mediump on mobile GPUs):
// each ray's t, NaN where the evaluator's bound on
// instructions ended it (GlslField::kMaxSteps).
template <class T>
std::vector<double> march_on_cpu(const std::string& text, const std::string& file, const UserMarcher& marcher,
                                 const std::map<std::string, std::vector<double>>& uniforms,
                                 const std::vector<std::pair<glm::dvec3, glm::dvec3>>& rays);

// The field's distance (its result's .x) at each point, in the driver's float.
std::vector<float> field_on_driver(const std::string& text, const std::string& file, const std::string& function,
                                   const std::map<std::string, std::vector<double>>& uniforms,
                                   const std::vector<glm::dvec3>& points, double seconds_limit = 60);

// A Shadertoy shader's image (its mainImage over width x height pixels, iResolution set, row 0 at the bottom as
// Shadertoy's fragCoord counts): RGBA per pixel.
std::vector<float> render_shadertoy(const std::string& text, const std::string& file, int width, int height,
                                    double seconds_limit = 60);

}  // namespace marchcheck::gpu
