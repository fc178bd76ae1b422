// Scene files: JSON text <-> Scene. Writing then reading gives back the same scene, bit for bit.
#pragma once

#include "marchcheck/meshes/io.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace marchcheck::sdf {

std::string scene_to_json(const Scene& scene);

// Reads a mesh node's source (a file path, or a generator such as "procedural:icosphere(1,4)") into triangles,
// throwing std::exception with a message naming it on failure: meshes::load_mesh_source unless a caller (a
// fuzzer that must not read files) passes another; an empty loader makes every mesh node and every glsl node (a
// compiler run on the text) an error.
using MeshLoader = std::function<meshes::Mesh(const std::string& source)>;

// Loads the triangles of every mesh node of the scene's trees. Throws SceneError "/json/path/mesh: problem".
void load_meshes(Scene& scene, const MeshLoader& loader = meshes::load_mesh_source);
// What loading changed in a tree's meshes (each mesh's "weld"), one line each, for the user to read.
std::vector<std::string> mesh_notes(const Node& root);

// source names the text in error messages (a file path); relative mesh paths are found beside it. Throws
// SceneError: "source:line:column: problem" for syntax errors, "source: /json/path: problem" for content errors.
Scene scene_from_json(std::string_view text, const std::string& source,
                      const MeshLoader& loader = meshes::load_mesh_source);

// A whole file's bytes (scene files, GLSL sources); nothing when it cannot be opened.
std::optional<std::string> read_text_file(const std::string& path);

// Reads a scene file; errors name the file.
Scene load_scene_file(const std::string& path, const MeshLoader& loader = meshes::load_mesh_source);

}  // namespace marchcheck::sdf
