// libFuzzer target: scene file text -> Scene -> tape -> evaluations. Any input may be refused with a SceneError
// or CompileError; anything else (a crash, another exception, a sanitizer report, a hang) is a finding. A scene
// that loads must also export to text that loads again, and evaluate without tripping the sanitizers.
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace marchcheck::sdf;
  Scene scene;
  try {
    // No mesh loader: fuzzed scenes must not read files or generate meshes (the mesh fuzzers cover those).
    scene = scene_from_json(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json", {});
  } catch (const SceneError&) {
    return 0;
  }
  (void)scene_from_json(scene_to_json(scene), "exported.json", {});  // must not throw: export is loadable
  Tape tape;
  try {
    tape = compile(scene.root, scene.time);
  } catch (const CompileError&) {
    return 0;
  }
  // The camera, the origin, a far point and one inside a unit sphere: values may be anything, even NaN, but
  // evaluating must stay within the tape's stacks and the sanitizers' rules.
  const glm::dvec3 points[] = {scene.camera.position, {0, 0, 0}, {1e6, -3e5, 2e4}, {0.25, 0.5, -0.125}};
  for (const glm::dvec3 p : points) {
    (void)evaluate<double>(tape, p);
    (void)evaluate<float>(tape, glm::vec3(p));
    (void)sample<double>(tape, p);
  }
  return 0;
}
