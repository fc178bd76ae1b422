// The straightforward port of the lee-flat shader that P1 compares the renderer with: what a user writes first
// (scalar float GLM, one call of a plain SDF function per step, the shader's loop, rows in parallel with oneTBB).
// It draws the same image as `marchcheck render lee-flat` and spends the same evaluations, so the two times
// compare the same work.
#pragma once

#include <cstdint>
#include <vector>

namespace marchcheck::sdf {
struct Scene;
}

namespace marchcheck::bench {

struct PortImage {
  int width = 0, height = 0;
  std::vector<float> rgb;   // linear RGB, row-major, as march::RenderResult::color
  std::uint64_t evals = 0;  // SDF calls, all stages
};

// Renders lee-flat at the scene's size and time. Only the camera (its lens model and ray generation) comes from
// the scene: the field, march, shading and shadow are written out by hand, as the shader does.
PortImage render_lee_flat_port(const sdf::Scene& lee_flat);

}  // namespace marchcheck::bench
