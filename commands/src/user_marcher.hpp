// `validate my.glsl --march NAME`: the user's own marcher, run on the GL driver, judged like a scene's. Internal
// to commands.
#pragma once

#include "marchcheck/gpu/user_marcher.hpp"
#include "marchcheck/sdf/scene.hpp"
#include "marchcheck/validation/validate.hpp"

#include <map>
#include <string>
#include <vector>

namespace marchcheck::commands {

// A GLSL file as its marcher runs: its text (a sweep's #defines overridden) and uniforms.
struct UserShader {
  std::string path, text;
  std::map<std::string, std::vector<double>> uniforms;
};

// The scene a GLSL file's marcher is judged in: the file's own (glsl_scene, with the shader's own limits), marched
// in float in steps of f.
sdf::Scene user_marcher_scene(const UserShader& shader, const gpu::UserMarcher& marcher);

// The marcher's rays through the scene's camera, marched on the driver and judged by validate's checks against the
// references of the scene; with the driver against the CPU (driver.*, cpu.*). Throws sdf::GlslError,
// gpu::DriverUnavailable, gpu::DriverError.
validation::SceneResult judge_user_marcher(const sdf::Scene& scene, const UserShader& shader,
                                            const gpu::UserMarcher& marcher, std::string& renderer,
                                            const validation::ValidateOptions& options = {});

// The shader with one of its own parameters set, as `--vary glsl.NAME=VALUE` asks: a #define's line rewritten
// (its line count kept), else a uniform it declares given the value. Throws sdf::SceneError naming the file when
// it has neither.
void set_shader_parameter(UserShader& shader, const std::string& name, const std::string& value);

}  // namespace marchcheck::commands
