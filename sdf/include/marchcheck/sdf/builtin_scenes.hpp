// The built-in scenes: the reference scenes of SEED-SCENES.md rebuilt in the distance-field language.
#pragma once

#include "marchcheck/sdf/scene.hpp"
#include "marchcheck/sdf/scene_file.hpp"

#include <string>
#include <vector>

namespace marchcheck::sdf {

std::vector<std::string> builtin_scene_names();

// Throws SceneError for a name that is not built in, or for a mesh it cannot load.
Scene builtin_scene(const std::string& name, const MeshLoader& loader = meshes::load_mesh_source);

// A built-in name, or else a scene file path.
Scene resolve_scene(const std::string& name_or_path, const MeshLoader& loader = meshes::load_mesh_source);

}  // namespace marchcheck::sdf
