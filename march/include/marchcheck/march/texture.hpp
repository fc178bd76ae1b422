// Image textures through OpenImageIO's TextureSystem. The project ships no photograph: the soil texture is
// generated (value-noise fBm) on first use into the temporary folder.
#pragma once

#include <glm/glm.hpp>

#include <string>

namespace marchcheck::march {

// Path of the generated soil/sand texture, created on first call (thread-safe).
const std::string& soil_texture_path();

// Bilinear lookup with wrapping at texture coordinates (s, t) in [0, 1).
glm::dvec3 sample_texture(const std::string& path, double s, double t);

}  // namespace marchcheck::march
