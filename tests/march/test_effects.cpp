// Each effect: its numbers on analytic set-ups, its zero cost when undeclared, its change to the image when declared.
#include "marchcheck/march/effects.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/node.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <utility>

namespace marchcheck::march {
namespace {

using V = glm::dvec3;

// Ground plane y = 0 with a sphere of radius 0.5 at (0, 1, 0) above it.
const sdf::Tape kGround = sdf::compile(sdf::unite({sdf::plane({0, 1, 0}, 0), sdf::translate({0, 1, 0}, sdf::sphere(0.5))}));

sdf::Light overhead(sdf::ShadowMode mode, sdf::ShadowBias bias) {
  sdf::Light l;
  l.type = sdf::LightType::directional;
  l.direction = {0, -1, 0};
  l.shadow = mode;
  l.bias = bias;
  return l;
}

MarchSettings seed_settings() {
  MarchSettings s;
  s.hit_eps = 0.01;
  s.max_steps = 200;
  s.max_dist = 100;
  return s;
}

TEST(Shadows, EveryHardStrategyDarkensTheAnalyticShadowAndLightsTheRest) {
  // Straight down, the sphere's shadow on the ground is the disc x^2 + z^2 < 0.25.
  for (auto bias : {sdf::ShadowBias::seed_offset, sdf::ShadowBias::seed_ignore, sdf::ShadowBias::scaled}) {
    SCOPED_TRACE(static_cast<int>(bias));
    const auto light = overhead(sdf::ShadowMode::hard, bias);
    // The hit point the march reports is up to hit_eps above the surface.
    for (const V p : {V(0, 0.005, 0), V(0.3, 0.005, -0.2)})
      EXPECT_EQ(shadow_visibility<double>(TapeField{&kGround}, p, V(0, 1, 0), V(0, 1, 0), INFINITY, 5.0, light,
                                          seed_settings(), {})
                    .visibility,
                0.0);
    for (const V p : {V(0.7, 0.005, 0), V(2, 0.005, 3)})
      EXPECT_EQ(shadow_visibility<double>(TapeField{&kGround}, p, V(0, 1, 0), V(0, 1, 0), INFINITY, 5.0, light,
                                          seed_settings(), {})
                    .visibility,
                1.0);
  }
}

TEST(Shadows, WithoutABiasTheShadowRayHitsItsOwnSurface) {
  // The broken variant: no offset at all. The seed strategy with bias factor 0 starts on the surface: acne.
  auto light = overhead(sdf::ShadowMode::hard, sdf::ShadowBias::seed_offset);
  light.bias_factor = 0;
  EXPECT_EQ(shadow_visibility<double>(TapeField{&kGround}, V(2, 0.005, 3), V(0, 1, 0), V(0, 1, 0), INFINITY, 5.0,
                                      light, seed_settings(), {})
                .visibility,
            0.0);
}

TEST(Shadows, SoftShadowsGoFromUmbraThroughPenumbraToLight) {
  for (auto variant : {sdf::SoftShadow::classic, sdf::SoftShadow::improved}) {
    SCOPED_TRACE(static_cast<int>(variant));
    auto light = overhead(sdf::ShadowMode::soft, sdf::ShadowBias::scaled);
    light.soft = variant;
    light.penumbra = 8;
    double previous = -1;
    for (double x : {0.0, 0.45, 0.55, 0.65, 1.5}) {
      const double v = shadow_visibility<double>(TapeField{&kGround}, V(x, 0.005, 0), V(0, 1, 0), V(0, 1, 0), INFINITY,
                                                 5.0, light, seed_settings(), {})
                           .visibility;
      EXPECT_GE(v, previous) << x;  // visibility grows away from the shadow's centre
      previous = v;
    }
    EXPECT_EQ(shadow_visibility<double>(TapeField{&kGround}, V(0, 0.005, 0), V(0, 1, 0), V(0, 1, 0), INFINITY, 5.0,
                                        light, seed_settings(), {})
                  .visibility,
              0.0);
    const double edge = shadow_visibility<double>(TapeField{&kGround}, V(0.55, 0.005, 0), V(0, 1, 0), V(0, 1, 0),
                                                  INFINITY, 5.0, light, seed_settings(), {})
                            .visibility;
    EXPECT_GT(edge, 0.0);
    EXPECT_LT(edge, 1.0) << "just outside the geometric shadow: penumbra";
  }
}

// The soft shadow's penumbra is k times the closest approach over distance: at a point in the penumbra, halving k
// halves the visibility exactly, in both variants (the steps do not depend on k, and doubling is exact). Broken
// variant: k left out of the classic formula.
TEST(Shadows, SoftShadowVisibilityIsProportionalToThePenumbraFactor) {
  for (auto variant : {sdf::SoftShadow::classic, sdf::SoftShadow::improved}) {
    auto light = overhead(sdf::ShadowMode::soft, sdf::ShadowBias::scaled);
    light.soft = variant;
    const auto at = [&](double k) {
      light.penumbra = k;
      return shadow_visibility<double>(TapeField{&kGround}, V(0.55, 0.005, 0), V(0, 1, 0), V(0, 1, 0), INFINITY, 5.0,
                                       light, seed_settings(), {})
          .visibility;
    };
    ASSERT_LT(at(8), 1.0) << "the point must be in the penumbra";
    EXPECT_DOUBLE_EQ(at(4), at(8) / 2) << static_cast<int>(variant);
  }
}

// The closest approach of the shadow ray from (x, 0.005, 0) straight up past the sphere of radius 0.5 at (0, 1, 0),
// over the distance: k min over t of (|(x, y(t), 0) - (0, 1, 0)| - 0.5) / t, sampled every 2.5e-5 in double (the
// sampling itself overestimates by under 1e-6 here). The classic estimate takes the minimum at the march's steps
// only, so it is never below that; the improved one (Quilez) estimates the approach between two steps from the
// two empty spheres, whose intersection circle is nearer the ray than the occluder can be, so it is never above.
// Broken variant: the improved correction y = h^2 / (2 h_prev) halved, which overshoots the true value.
TEST(Shadows, ClassicAndImprovedSoftShadowsBracketTheTrueClosestApproach) {
  auto light = overhead(sdf::ShadowMode::soft, sdf::ShadowBias::scaled);
  light.penumbra = 8;
  for (double x : {0.52, 0.55, 0.58, 0.62}) {
    const auto visibility = [&](sdf::SoftShadow variant) {
      light.soft = variant;
      return shadow_visibility<double>(TapeField{&kGround}, V(x, 0.005, 0), V(0, 1, 0), V(0, 1, 0), INFINITY, 5.0,
                                       light, seed_settings(), {})
          .visibility;
    };
    double truth = 1;
    for (int i = 1; i <= 200000; ++i) {
      const double t = 5.0 * i / 200000, y = 0.005 + t;
      truth = std::min(truth, 8 * (std::hypot(x, y - 1) - 0.5) / t);
    }
    ASSERT_LT(truth, 1.0) << x;
    EXPECT_GE(visibility(sdf::SoftShadow::classic), truth - 1e-6) << x;
    EXPECT_LE(visibility(sdf::SoftShadow::improved), truth + 1e-6) << x;
  }
}

// A thin slab (y in [0.99, 1.01]) above the ground under a field twice as steep as its distance. A marcher told to
// step by half of f (step_scale 0.5, the sphere marcher), or by f / L (the scaled one and the relaxed one, L = 2),
// cannot jump it, and neither may the shadow rays of the same march (the relaxed one's first step, 1.6 f / 2, passes
// the slab and steps back onto it). Broken variants: soft shadows stepping by f, ignoring step_scale (drift fixed
// here: from y = 0.005 the first step of 1.97 lands past the slab and the point is lit), the relaxed marcher
// ignoring L (march-relaxed-ignores-lipschitz).
TEST(Shadows, EveryShadowStepsAsTheMarcherDoesOnASteepField) {
  const auto steep = [](auto p) { return decltype(p.x)(2) * (std::abs(p.y - decltype(p.x)(1)) - decltype(p.x)(0.01)); };
  MarchSettings half = seed_settings();
  half.step_scale = 0.5;
  MarchSettings scaled = seed_settings();
  scaled.marcher = sdf::Marcher::scaled;
  MarchSettings relaxed = scaled;
  relaxed.marcher = sdf::Marcher::relaxed;
  MarchContext steep_context;
  steep_context.lipschitz = 2;
  for (auto mode : {sdf::ShadowMode::hard, sdf::ShadowMode::soft})
    for (const auto& [settings, context] :
         {std::pair{half, MarchContext{}}, std::pair{scaled, steep_context}, std::pair{relaxed, steep_context}}) {
      SCOPED_TRACE(std::string(mode == sdf::ShadowMode::hard ? "hard" : "soft") + ", marcher " +
                   std::to_string(static_cast<int>(settings.marcher)) + ", step_scale " +
                   std::to_string(settings.step_scale));
      const auto light = overhead(mode, sdf::ShadowBias::scaled);
      EXPECT_EQ(shadow_visibility<double>(steep, V(0, 0.005, 0), V(0, 1, 0), V(0, 1, 0), INFINITY, 5.0, light, settings,
                                          context)
                    .visibility,
                0.0);
    }
}

// One pixel looking straight down -z at the plane z = 0 (normal and view both +z, exactly, whatever hit_eps
// leaves), lit by a white directional light from l = (0.6, 0, 0.8): n.l = 0.8. No ambient unless a test sets it.
sdf::Scene one_pixel_plane(const sdf::Material& material) {
  sdf::Scene s;
  s.materials = {material};
  s.root = sdf::plane({0, 0, 1}, 0, 0);
  s.width = s.height = 1;
  s.camera.position = {0, 0, 5};
  s.camera.target = {0, 0, 0};
  sdf::Light light;
  light.direction = {-0.6, 0, -0.8};
  s.lights = {light};
  s.effects.ambient = 0;
  s.march.hit_eps = 1e-4;
  return s;
}

V pixel(const RenderResult& r) {
  const float* c = r.color.at(0, 0);
  return {c[0], c[1], c[2]};
}

sdf::Material grey(double albedo) {
  sdf::Material m;
  m.name = "grey";
  m.color = V(albedo);
  return m;
}

// Colours are float: 1e-6 is a few ulps of the values here.
constexpr double kShadeTol = 1e-6;

// Lambert: albedo * n.l; Blinn-Phong: strength (n.h)^shininess with h = normalize(l + v) = normalize(0.6, 0, 1.8);
// Phong: strength (r.v)^shininess with r = reflect(-l, n) = (-0.6, 0, 0.8), so r.v = 0.8. Broken variants: h
// built as l - v (n.h < 0: no highlight); reflect without its factor 2 (r.v = 0); the strength taken as 1.
TEST(Shading, DiffuseAndBothSpecularModelsMatchTheirClosedForms) {
  const V lambert = pixel(render(one_pixel_plane(grey(0.5))));
  EXPECT_NEAR(lambert.x, 0.5 * 0.8, kShadeTol);
  sdf::Material blinn = grey(0.5);
  blinn.specular = sdf::SpecularModel::blinn;
  blinn.specular_strength = 0.7;
  blinn.shininess = 8;
  const double n_h = 1.8 / std::sqrt(0.6 * 0.6 + 1.8 * 1.8);
  EXPECT_NEAR(pixel(render(one_pixel_plane(blinn))).x, 0.4 + 0.7 * std::pow(n_h, 8), kShadeTol);
  sdf::Material phong = blinn;
  phong.specular = sdf::SpecularModel::phong;
  EXPECT_NEAR(pixel(render(one_pixel_plane(phong))).x, 0.4 + 0.7 * std::pow(0.8, 8), kShadeTol);
  // Lit from below (n.l = -0.8), over an ambient of 1 (final colours are clamped at 0): each diffuse rule as
  // declared. Broken variant: the floor ignored.
  sdf::Scene below = one_pixel_plane(grey(0.5));
  below.lights[0].direction = {-0.6, 0, 0.8};
  below.effects.ambient = 1;
  EXPECT_NEAR(pixel(render(below)).x, 0.5, kShadeTol);
  below.effects.diffuse = sdf::Diffuse::floor;
  below.effects.diffuse_floor = 0.2;
  EXPECT_NEAR(pixel(render(below)).x, 0.5 + 0.5 * 0.2, kShadeTol);
  below.effects.diffuse = sdf::Diffuse::unclamped;
  EXPECT_NEAR(pixel(render(below)).x, 0.5 - 0.5 * 0.8, kShadeTol);
}

// A slab of index 1.5 seen head-on over a floor: Schlick's F0 = 0.04 of the background (reflected up) and 0.96 of
// the lit floor (refracted straight through). Broken variant: the cosine given with the wrong sign (F = 30.8).
TEST(Shading, TransparencyWeighsReflectionAndRefractionBySchlick) {
  sdf::Scene s = one_pixel_plane(grey(0.5));
  sdf::Material glass = grey(0.9);
  glass.name = "glass";
  glass.transparency = 1;
  glass.ior = 1.5;
  s.materials.push_back(glass);
  s.root = sdf::unite({sdf::plane({0, 0, 1}, 0, 0), sdf::translate({0, 0, 2}, sdf::box({10, 10, 0.5}, 1))});
  s.lights[0].direction = {0, 0, -1};  // overhead: the floor shows its albedo, 0.5
  s.effects.background = V(0.2);
  s.effects.max_bounces = 2;
  const double f0 = std::pow((1 - 1.5) / (1 + 1.5), 2);
  // The refracted ray crosses the slab's two faces, each hit within hit_eps: the floor is the same flat colour.
  EXPECT_NEAR(pixel(render(s)).x, f0 * 0.2 + (1 - f0) * 0.5, kShadeTol);
}

TEST(Fresnel, SchlickAtNormalIncidenceIsTheReflectanceOfTheInterface) {
  for (double n2 : {1.33, 1.5, 2.4}) EXPECT_DOUBLE_EQ(schlick_fresnel(1.0, 1.0, n2), std::pow((1 - n2) / (1 + n2), 2));
  EXPECT_DOUBLE_EQ(schlick_fresnel(0.0, 1.0, 1.5), 1.0) << "grazing incidence reflects everything";
}

TEST(Refraction, ASlabOffsetsTheRayByTheClosedFormAmount) {
  // Slab of thickness 1 (|y| < 0.5), wide in x and z; ray at 30 degrees from the normal, index 1.5.
  const sdf::Tape slab = sdf::compile(sdf::box({50, 0.5, 50}));
  const double theta = 30 * std::numbers::pi / 180, ior = 1.5;
  const V d(std::sin(theta), -std::cos(theta), 0);
  const V entry(0, 0.5, 0);
  MarchSettings s = seed_settings();
  s.hit_eps = 1e-9;
  s.max_steps = 10000;
  const auto r = refract_through<double>(TapeField{&slab}, entry, V(0, 1, 0), d, ior, s, {}, 1e-6);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(glm::length(r.exit_direction - d), 0.0, 1e-6) << "leaves parallel to how it came in";
  const double theta_t = std::asin(std::sin(theta) / ior);
  const double offset = 1.0 * std::sin(theta - theta_t) / std::cos(theta_t);
  // Perpendicular distance from the exit point to the incoming line.
  const V w = r.exit_point - entry;
  const double lateral = glm::length(w - d * glm::dot(w, d));
  // Entry and exit points sit 2 (hit_eps + 1e-6) off the surface along the normal, each moving the line
  // sideways by up to that much: 4e-6 of slack; the march itself is exact to 1e-9 here.
  EXPECT_NEAR(lateral, offset, 4e-6);
}

// A scene to switch effects on: sphere over a ground plane, one point light.
sdf::Scene base_scene() {
  sdf::Scene s;
  s.name = "effects";
  s.materials = {{"ball", {0.8, 0.3, 0.2}}, {"ground", {0.6, 0.6, 0.6}}};
  s.root = sdf::unite({sdf::translate({0, 1, 0}, sdf::sphere(1, 0)), sdf::plane({0, 1, 0}, 0, 1)});
  s.width = 64;
  s.height = 48;
  s.camera.position = {0, 2.5, 5};
  s.camera.target = {0, 0.8, 0};
  s.camera.fov_deg = 60;
  sdf::Light light;
  light.type = sdf::LightType::point;
  light.position = {2, 5, 2};
  s.lights = {light};
  s.march.hit_eps = 1e-3;
  return s;
}

// A grey scene stays grey under every effect that shades: each treats the channels alike. Broken variant:
// ambient occlusion left out of one channel's ambient term.
TEST(Shading, AGreySceneStaysGreyUnderEveryShadingEffect) {
  sdf::Scene s = base_scene();
  s.materials = {grey(0.6), grey(0.4)};
  s.effects.ambient = 0.3;
  s.effects.ao = sdf::AmbientOcclusion::samples;
  s.lights[0].shadow = sdf::ShadowMode::soft;
  s.materials[0].specular = sdf::SpecularModel::blinn;
  s.materials[0].specular_strength = 0.5;
  const RenderResult r = render(s);
  int lit = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const float* c = r.color.at(x, y);
      lit += c[0] > 0;
      EXPECT_EQ(c[0], c[1]) << x << ", " << y;
      EXPECT_EQ(c[0], c[2]) << x << ", " << y;
    }
  EXPECT_GT(lit, s.width * s.height / 2);
}

struct EffectCase {
  const char* name;
  const char* stage;  // the stage the effect spends its evaluations in ("" = shading only: no evaluations)
  std::function<void(sdf::Scene&)> declare;
};

std::vector<EffectCase> effect_cases() {
  return {
      {"hard shadow", "shadow", [](sdf::Scene& s) { s.lights[0].shadow = sdf::ShadowMode::hard; }},
      {"soft shadow", "shadow", [](sdf::Scene& s) { s.lights[0].shadow = sdf::ShadowMode::soft; }},
      {"sampled ao", "ao", [](sdf::Scene& s) { s.effects.ao = sdf::AmbientOcclusion::samples; }},
      {"reflection", "reflection",
       [](sdf::Scene& s) {
         s.materials[1].reflectivity = 0.5;
         s.effects.max_bounces = 2;
       }},
      {"refraction", "refraction",
       [](sdf::Scene& s) {
         s.materials[0].transparency = 0.8;
         s.effects.max_bounces = 2;
       }},
      {"specular", "",
       [](sdf::Scene& s) {
         s.materials[0].specular = sdf::SpecularModel::phong;
         s.materials[0].specular_strength = 0.5;
       }},
      {"texture", "",
       [](sdf::Scene& s) {
         s.materials[1].texture = sdf::TextureMapping::planar;
         s.materials[1].texture_scale = 0.5;
       }},
      {"step ao", "", [](sdf::Scene& s) { s.effects.ao = sdf::AmbientOcclusion::steps; }},
      {"glow", "", [](sdf::Scene& s) { s.effects.glow = 1; }},
      {"fog", "", [](sdf::Scene& s) { s.effects.fog = 0.2; }},
      {"toon", "",
       [](sdf::Scene& s) {
         s.effects.shading = sdf::Shading::toon;
         s.effects.silhouette = 0.2;
       }},
      {"ramp", "",
       [](sdf::Scene& s) {
         s.materials[0].ramp_value = 0.5;
         s.effects.ramp = {{0, 0, 1}, {0, 1, 0}};
       }},
      {"floor diffuse", "", [](sdf::Scene& s) { s.effects.diffuse = sdf::Diffuse::floor; }},
  };
}

class Effect : public ::testing::TestWithParam<size_t> {};

TEST_P(Effect, CostsNothingUndeclaredAndChangesTheImageDeclared) {
  const auto c = effect_cases()[GetParam()];
  sdf::Scene with = base_scene();
  with.materials[1].reflectivity = 0;
  if (std::string(c.name) == "glow") with.root = sdf::translate({0, 1, 0}, sdf::sphere(1, 0));  // misses to glow on
  sdf::Scene without = with;
  c.declare(with);
  const RenderResult a = render(without), b = render(with);
  EXPECT_NE(a.color.pixels, b.color.pixels) << "declaring " << c.name << " must change the image";
  for (const char* stage : {"shadow", "ao", "reflection", "refraction"}) {
    EXPECT_EQ(a.stages.at(stage).evals, 0u) << stage;
    EXPECT_EQ(a.stages.at(stage).seconds, 0.0) << stage;
  }
  if (std::string(c.stage).empty()) {
    EXPECT_EQ(a.total_evals, b.total_evals) << c.name << " is shading only: it must cost no evaluation";
  } else {
    EXPECT_GT(b.stages.at(c.stage).evals, 0u);
    EXPECT_GT(b.stages.at(c.stage).seconds, 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(All, Effect, ::testing::Range<size_t>(0, effect_cases().size()));

TEST(Pipeline, ADepthOnlyRenderEvaluatesNoNormal) {
  sdf::Scene s = base_scene();
  s.lights.clear();
  s.effects.ambient = 0;
  const RenderResult depth_only = render(s, {Aov::depth});
  EXPECT_EQ(depth_only.stages.at("normal").evals, 0u);
  EXPECT_EQ(depth_only.stages.at("material").evals, 0u);
  EXPECT_EQ(depth_only.total_evals, depth_only.stages.at("march").evals);
  EXPECT_GT(render(s, {Aov::normal}).stages.at("normal").evals, 0u) << "asking for the normal AOV computes normals";
}

// Ambient light alone shades without a normal: materials are looked up, no normal is estimated. Broken variant:
// the normal gate opened by anything that shades (materials), not by what needs the normal.
TEST(Pipeline, AnAmbientOnlyRenderEvaluatesMaterialsButNoNormal) {
  sdf::Scene s = base_scene();
  s.lights.clear();
  s.effects.ambient = 0.5;
  const RenderResult ambient_only = render(s, {});
  EXPECT_EQ(ambient_only.stages.at("normal").evals, 0u);
  EXPECT_GT(ambient_only.stages.at("material").evals, 0u);
}

TEST(Mirror, ShowsTheReflectedObjectWhereGeometrySays) {
  // A mirror floor and a red sphere; the camera looks at the floor point whose mirror ray hits the sphere.
  sdf::Scene s = base_scene();
  s.materials[0].color = {1, 0, 0};
  s.materials[1].color = {0, 0, 1};
  s.materials[1].reflectivity = 1;
  s.effects.max_bounces = 1;
  s.effects.ambient = 0.3;
  s.lights.clear();
  // Eye (0, 1, 4); floor point (0, 0, 2): the reflected ray heads to (0, 1, 0), the sphere's centre.
  s.camera.position = {0, 1, 4};
  s.camera.target = {0, 0, 2};
  s.width = s.height = 33;
  const RenderResult r = render(s);
  const float* centre = r.color.at(16, 16);
  EXPECT_NEAR(centre[0], 0.3 * 1.0, 1e-6) << "the sphere's red, lit by ambient only";
  EXPECT_NEAR(centre[2], 0.0, 1e-6);
  s.effects.max_bounces = 0;
  const RenderResult without = render(s);  // kept alive: a pointer into a temporary's pixels would dangle
  EXPECT_NEAR(without.color.at(16, 16)[2], 0.3, 1e-6) << "without bounces the floor shows its own blue";
}

TEST(Fog, BlendsTowardTheFogColourByExpOfDistance) {
  sdf::Scene s = base_scene();
  s.lights.clear();
  s.effects.ambient = 1;
  s.materials[1].color = glm::dvec3(1);
  s.effects.fog = 0.3;
  s.effects.fog_color = glm::dvec3(0);
  const RenderResult r = render(s);
  for (int x : {5, 30, 58}) {
    const float depth = *r.depth.at(x, 45);
    ASSERT_TRUE(std::isfinite(depth));
    EXPECT_NEAR(r.color.at(x, 45)[1], std::exp(-0.3 * depth), 1e-6);
  }
}

TEST(Toon, DiffuseTakesOnlyTheBandValues) {
  sdf::Scene s = base_scene();
  s.effects.shading = sdf::Shading::toon;
  s.effects.ambient = 0;
  s.materials[0].color = glm::dvec3(1);
  s.materials[1].color = glm::dvec3(1);
  const RenderResult r = render(s);
  for (size_t i = 0; i < r.color.pixels.size(); i += 3) {
    if (*r.outcome.at(static_cast<int>(i / 3) % 64, static_cast<int>(i / 3) / 64) != 0) continue;
    const float v = r.color.pixels[i];
    const bool band = std::abs(v - 0.1f) < 1e-6 || std::abs(v - 0.4f) < 1e-6 || std::abs(v - 0.7f) < 1e-6 ||
                      std::abs(v - 1.0f) < 1e-6 || v == 0.0f;
    ASSERT_TRUE(band) << v;
  }
}

}  // namespace
}  // namespace marchcheck::march

namespace marchcheck::march {
namespace {

// Broken variants: a mesh's pixel left unmarked, so unshaded (march-mesh-surface-unmarked); a ray that misses every
// mesh taken as a hit on one (march-mesh-miss-taken); the march not stopped at a mesh's hit, so a field surface
// behind the mesh is taken (march-mesh-march-not-stopped); a packet filled whole marching every ray to the settings'
// max_dist, past its own end (march-packet-whole-ray-end-ignored).
TEST(MeshOcclusion, MeshAndFieldHideEachOtherAtTheirExactDistances) {
  // A unit sphere at the origin; a mesh wall at z = 1 over x < 0 (in front of the sphere, whose nearest point
  // is at z = 1) and one at z = -2 over x > 0 (behind it).
  sdf::Scene s = base_scene();
  s.root = sdf::sphere(1, 0);
  s.lights.clear();
  s.effects.ambient = 1;
  s.width = s.height = 41;
  s.camera.position = {0, 0, 5};
  s.camera.target = {0, 0, 0};
  sdf::SceneMesh wall;
  wall.vertices = {{-3, -3, 1}, {0, -3, 1}, {0, 3, 1}, {-3, 3, 1}, {0, -3, -2}, {3, -3, -2}, {3, 3, -2}, {0, 3, -2}};
  wall.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  wall.material = 1;
  s.meshes = {wall};
  const RenderResult r = render(s);
  const Camera cam(s.camera, s.width, s.height);
  // Left of centre the front wall hides the sphere: depth is the closed-form distance to the plane z = 1
  // (Embree works in float: 1e-5 at distance 4).
  const Ray left = cam.ray(17.5, 20.5);
  EXPECT_NEAR(*r.depth.at(17, 20), (5 - 1) / -left.direction.z, 1e-5);
  EXPECT_EQ(*r.id.at(17, 20), 1.0f);
  // Right of centre the sphere hides the back wall: depth is the closed-form sphere hit, to within the float
  // march's hit_eps (1e-3) over the cosine of incidence (> 0.5 here).
  const Ray right = cam.ray(24.5, 20.5);
  const double b = glm::dot(right.origin, right.direction), c = glm::dot(right.origin, right.origin) - 1;
  EXPECT_NEAR(*r.depth.at(24, 20), -b - std::sqrt(b * b - c), 1e-3 / 0.5);
  EXPECT_EQ(*r.id.at(24, 20), 0.0f);
  // Beyond the sphere on the right, the back wall.
  const Ray far_right = cam.ray(33.5, 20.5);
  EXPECT_NEAR(*r.depth.at(33, 20), (5 + 2) / -far_right.direction.z, 1e-5);
  EXPECT_GT(r.stages.at("mesh").seconds, 0.0);
  // With the front wall alone, a ray past the sphere on the right misses every surface: the background, no depth, no
  // material.
  s.meshes[0].vertices.resize(4);
  s.meshes[0].triangles.resize(2);
  const RenderResult front = render(s);
  EXPECT_EQ(*front.depth.at(33, 20), INFINITY);
  EXPECT_EQ(*front.id.at(33, 20), -1.0f);
  // Without meshes the stage is never entered.
  s.meshes.clear();
  EXPECT_EQ(render(s).stages.at("mesh").seconds, 0.0);
}

}  // namespace
}  // namespace marchcheck::march
