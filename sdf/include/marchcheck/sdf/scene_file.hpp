// Scene files: JSON text <-> Scene. Writing then reading gives back the same scene, bit for bit.
#pragma once

#include "marchcheck/sdf/scene.hpp"

#include <functional>
#include <string>
#include <string_view>

namespace marchcheck::sdf {

std::string scene_to_json(const Scene& scene);

// Reads a mesh node's source (a file path, or a generator such as "procedural:icosphere(1,4)") into triangles,
// throwing std::exception with a message naming it on failure. The sdf module reads no mesh formats: meshes/ does,
// and the program passes validation::mesh_loader().
using MeshLoader = std::function<TriangleMesh(const std::string& source)>;

// Loads the triangles of every mesh node of the scene's trees. Throws SceneError "/json/path/mesh: problem";
// without a loader, a tree with a mesh node is an error.
void load_meshes(Scene& scene, const MeshLoader& loader);

// source names the text in error messages (a file path); relative mesh paths are found beside it. Throws
// SceneError: "source:line:column: problem" for syntax errors, "source: /json/path: problem" for content errors.
Scene scene_from_json(std::string_view text, const std::string& source, const MeshLoader& meshes = {});

// Reads a scene file; errors name the file.
Scene load_scene_file(const std::string& path, const MeshLoader& meshes = {});

}  // namespace marchcheck::sdf
