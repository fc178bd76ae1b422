// libFuzzer target: scene file text -> Scene -> tape -> evaluations. Any input may be refused with a SceneError
// or CompileError; anything else (a crash, another exception, a sanitizer report, a hang) is a finding. A scene
// that loads must also export to text that loads again, and evaluate without tripping the sanitizers; and where
// its tape has interval rules, the interval over a small box around each point holds the double values at the
// box's corners and centre (a trap otherwise: an interval rule that lets a value escape, on any tree).
#include "marchcheck/sdf/interval.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <cmath>
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
  if (!interval_supported(tape)) return 0;
  for (const glm::dvec3 c : points) {
    const double h = 1e-3 * (1 + glm::length(c));
    const glm::vec<3, Interval> box(Interval(c.x - h, c.x + h), Interval(c.y - h, c.y + h), Interval(c.z - h, c.z + h));
    const Interval range = evaluate(tape, box);
    for (int corner = 0; corner < 9; ++corner) {
      const glm::dvec3 q = corner == 8 ? c : c + h * glm::dvec3(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1);
      const double v = evaluate<double>(tape, q);
      // The double tape's own rounding: ulps of the largest values it meets, which the interval's ends reach.
      const double ends = std::max(std::abs(range.lo), std::abs(range.hi));
      const double slack = 1e-9 * (1 + std::abs(v) + (std::isfinite(ends) ? ends : 0));
      if (std::isfinite(v) && !(range.lo - slack <= v && v <= range.hi + slack)) __builtin_trap();
    }
  }
  return 0;
}
