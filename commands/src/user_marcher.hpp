// `validate my.glsl --march NAME`: the user's own marcher, run on the GL driver, judged like a scene's. Internal
// to commands.
#pragma once

#include "marchcheck/gpu/user_marcher.hpp"
#include "marchcheck/sdf/scene.hpp"
#include "marchcheck/validation/validate.hpp"

#include <string>
#include <vector>

namespace marchcheck::commands {

// The scene a GLSL file's marcher is judged in: the file's own (glsl_scene), marched in float in steps of f,
// with the step limit, far distance and hit threshold the shader names (MAX_STEPS, MAX_DIST, SURF_DIST or their
// common spellings). `about` says what was read.
sdf::Scene user_marcher_scene(const std::string& path, const gpu::UserMarcher& marcher, std::string& about);

// The marcher's rays through the scene's camera, marched on the driver and judged by validate's checks against the
// references of the scene. Throws sdf::GlslError, gpu::DriverUnavailable, gpu::DriverError.
validation::SceneResult judge_user_marcher(const sdf::Scene& scene, const gpu::UserMarcher& marcher,
                                            std::string& renderer,
                                              const validation::ValidateOptions& options = {});

}  // namespace marchcheck::commands
