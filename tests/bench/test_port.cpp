// P1 compares like with like only if the straightforward port draws the renderer's image with the renderer's
// evaluations; this checks both (never the timing).
#include "lee_flat_port.hpp"

#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace sdf = marchcheck::sdf;
namespace march = marchcheck::march;
using marchcheck::bench::render_lee_flat_port;

namespace {

// A quarter of the built-in size keeps the test fast; the camera's intrinsics keep the same centre.
sdf::Scene small_lee_flat() {
  sdf::Scene scene = sdf::builtin_scene("lee-flat");
  scene.width = 320;
  scene.height = 180;
  scene.camera.fx = scene.camera.fy = 150;
  return scene;
}

struct Difference {
  double max_color = 0;
  std::int64_t evals = 0;
};

Difference compare(const sdf::Scene& project_scene, const sdf::Scene& port_scene) {
  const march::RenderResult project = march::render(project_scene);
  const auto port = render_lee_flat_port(port_scene);
  Difference d;
  d.evals = static_cast<std::int64_t>(project.total_evals) - static_cast<std::int64_t>(port.evals);
  for (size_t i = 0; i < port.rgb.size(); ++i)
    d.max_color = std::max(d.max_color, static_cast<double>(std::abs(port.rgb[i] - project.color.pixels[i])));
  return d;
}

// The port shades in float, the renderer in double, from the same float march: colours in [0, 1] differ by float
// rounding of a dozen operations and pow(x, 10), which multiplies a relative error by 10: 1e-4 is far above that
// and far below any change of hit, normal or shadow.
constexpr double kColorTolerance = 1e-4;

TEST(LeeFlatPort, SameImageAndEvaluationsAsTheRenderer) {
  const sdf::Scene scene = small_lee_flat();
  const Difference d = compare(scene, scene);
  EXPECT_EQ(d.evals, 0);
  EXPECT_LT(d.max_color, kColorTolerance);
}

// The comparison can fail: a renderer with a hit threshold of 0.012 instead of the port's 0.01 is caught.
TEST(LeeFlatPort, ADifferentHitThresholdIsCaught) {
  sdf::Scene changed = small_lee_flat();
  changed.march.hit_eps = 0.012;
  const Difference d = compare(changed, small_lee_flat());
  EXPECT_NE(d.evals, 0);
  EXPECT_GT(d.max_color, kColorTolerance);
}

}  // namespace
