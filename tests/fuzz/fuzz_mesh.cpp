// libFuzzer target for one mesh format (MARCHCHECK_FUZZ_EXT: "obj", "off", "ply" or "stl"): bytes -> file ->
// load_mesh -> inspect. A MeshError is the expected refusal; anything else is a finding. load_mesh reads paths
// only (OpenMesh picks its reader by extension), hence the file.
#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/io.hpp"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

const std::string& scratch_path() {
  static const std::string path = (std::filesystem::temp_directory_path() /
                                   ("marchcheck-fuzz-" + std::to_string(::getpid()) + "." MARCHCHECK_FUZZ_EXT))
                                      .string();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace marchcheck::meshes;
  {
    std::ofstream out(scratch_path(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  Mesh mesh;
  try {
    mesh = load_mesh(scratch_path());
  } catch (const MeshError&) {
    return 0;
  }
  // Outside the try: a loaded mesh is valid (every index names a vertex), so inspect must not throw.
  (void)inspect(mesh);
  return 0;
}
