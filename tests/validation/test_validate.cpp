// The checks on the built-in scenes: every correct scene passes, every defect variant fails on the check that
// names its defect.
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/validation/validate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

namespace marchcheck::validation {
namespace {

const Check* find(const SceneResult& r, const std::string& name) {
  auto it = std::find_if(r.checks.begin(), r.checks.end(), [&](const Check& c) { return c.name == name; });
  return it == r.checks.end() ? nullptr : &*it;
}

// Each seed defect and the check that catches it.
const std::map<std::string, std::string> kDefectTable = {
    {"lee-flat-defect-bias", "shadow.false_shadow"},
    {"lee-terrain-defect-lipschitz", "march.safe_step_ratio"},
    {"crum-torus-defect-fov", "camera.fov_err_deg"},
    {"crum-smooth-defect-intersect", "hit.false_hit"},
    {"crum-smooth-defect-subtract", "hit.false_hit"},
    {"crum-lattice-defect-lipschitz", "hit.overshoot"},
    {"fogerty-defect-steps", "hit.undecided"},
    {"fogerty-defect-miss0", "hit.false_hit"},
    {"fogerty-defect-camera", "image.pixels_over"},
    {"warped-defect-unnormalised", "camera.ray_norm_err"},
    {"warped-defect-lipschitz", "hit.overshoot"},
    {"flafla-torus-defect-no-drawdist", "hit.undecided"},
};

TEST(DefectTable, EveryDefectVariantFailsOnTheCheckThatNamesIt) {
  for (const auto& [scene, check] : kDefectTable) {
    const SceneResult r = validate_scene(sdf::builtin_scene(scene));
    const Check* c = find(r, check);
    ASSERT_NE(c, nullptr) << scene << " has no " << check;
    EXPECT_FALSE(c->pass) << scene << ": " << check << " = " << c->value << " <= " << c->limit;
    EXPECT_FALSE(r.pass()) << scene;
  }
}

TEST(CorrectScenes, PassEveryCheck) {
  // crum-lattice and crum-mandelbulb are open findings (see the validation issue): they are reported, not hidden.
  for (const auto& name : sdf::builtin_scene_names()) {
    const sdf::Scene scene = sdf::builtin_scene(name);
    if (!scene.defects.empty() || name == "crum-lattice" || name == "crum-mandelbulb") continue;
    const SceneResult r = validate_scene(scene);
    for (const auto& c : r.checks) EXPECT_TRUE(c.pass) << name << ": " << c.name << " = " << c.value << " > " << c.limit;
  }
}

TEST(Limits, SceneLimitsReplaceDefaultsAndSayWhose) {
  sdf::Scene s = sdf::builtin_scene("fogerty-defect-steps");
  EXPECT_FALSE(validate_scene(s).pass());
  s.limits["hit.undecided"] = 0.5;
  const SceneResult r = validate_scene(s);
  const Check* c = find(r, "hit.undecided");
  ASSERT_NE(c, nullptr);
  EXPECT_TRUE(c->pass);
  EXPECT_EQ(c->limit_source, "scene");
  EXPECT_EQ(find(r, "hit.false_hit")->limit_source, "default");
}

}  // namespace
}  // namespace marchcheck::validation
