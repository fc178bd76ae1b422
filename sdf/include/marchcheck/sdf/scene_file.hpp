// Scene files: JSON text <-> Scene. Writing then reading gives back the same scene, bit for bit.
#pragma once

#include "marchcheck/sdf/scene.hpp"

#include <string>
#include <string_view>

namespace marchcheck::sdf {

std::string scene_to_json(const Scene& scene);

// source names the text in error messages (a file path). Throws SceneError: "source:line:column: problem" for
// syntax errors, "source: /json/path: problem" for content errors.
Scene scene_from_json(std::string_view text, const std::string& source);

// Reads a scene file; errors name the file.
Scene load_scene_file(const std::string& path);

}  // namespace marchcheck::sdf
