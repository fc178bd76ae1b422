// Image textures through OpenImageIO's TextureSystem: a material's own image (texture_file), or the soil texture the
// project generates (value-noise fBm) on first use into the temporary folder, as it ships no photograph.
#pragma once

#include "marchcheck/sdf/scene.hpp"

#include <glm/glm.hpp>

#include <string>

namespace marchcheck::march {

// Path of the generated soil/sand texture, created on first call (thread-safe).
const std::string& soil_texture_path();

// The image a material's texture samples: its texture_file, or the soil.
const std::string& texture_path(const sdf::Material& material);

// Throws sdf::SceneError naming the material and the file when OpenImageIO cannot read a texture_file as an image.
void check_texture_files(const sdf::Scene& scene);

// Bilinear lookup with wrapping at texture coordinates (s, t) in [0, 1); a grey image gives grey.
glm::dvec3 sample_texture(const std::string& path, double s, double t);

}  // namespace marchcheck::march
