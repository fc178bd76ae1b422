// Any scene as GLSL: its field as a map() that marchcheck's GLSL evaluator computes bit for bit as the tape does
// in float, and a self-contained Shadertoy shader around it.
#pragma once

#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <string>

namespace marchcheck::sdf {

// `vec2 map(vec3 p)`: the compiled tree at `time`, one statement per tape instruction over GLSL kernels that mirror
// the C++ ones operation for operation, its constants rounded to float as the tape's are; .y is the deciding
// material (-1: none). Throws SceneError naming the scene (`name`) when an operator has no GLSL form (meshes,
// GLSL fields) and says why.
std::string glsl_map(const Node& root, double time, const std::string& name);

// The scene as a Shadertoy shader (mainImage) that draws what marchcheck's renderer draws: glsl_map, the scene's
// camera (every model, lens distortion included), marcher with its limits (MAX_STEPS, MAX_DIST, SURF_DIST),
// normals, triangle meshes, lights, hard and soft shadows, the soil texture, ambient occlusion, reflection and
// refraction to the scene's depth, glow and fog, at the scene's time. Throws SceneError as glsl_map.
std::string shadertoy_shader(const Scene& scene);

}  // namespace marchcheck::sdf
