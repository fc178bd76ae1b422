// The rebuilt seed scenes draw what the original shaders draw: the facts of ../shared/SEED-SCENES.md, as numbers.
#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <set>

namespace marchcheck::march {
namespace {

using glm::dvec3;

// lee's ray, computed as its shader does: pixel (u, v) with v counted up from the bottom row, xy = ((u, v) - c) / f,
// the distortion applied forward, the ray normalize(x, y, 1) turned by Ry Rx (theta = -yaw, phi = pitch), from
// the eye (-6 cos phi sin theta, 6 sin phi, -6 cos phi cos theta).
Ray lee_shader_ray(double u, double v, double width, double height, double yaw, double pitch) {
  glm::dvec2 xy((u - width / 2) / 600, (v - height / 2) / 600);
  xy *= 1 + 0.3 * glm::dot(xy, xy);
  const dvec3 ray = glm::normalize(dvec3(xy, 1));
  const double theta = -yaw, phi = pitch;
  const glm::dmat3 ry(dvec3(std::cos(theta), 0, -std::sin(theta)), dvec3(0, 1, 0),
                      dvec3(std::sin(theta), 0, std::cos(theta)));
  const glm::dmat3 rx(dvec3(1, 0, 0), dvec3(0, std::cos(phi), std::sin(phi)), dvec3(0, -std::sin(phi), std::cos(phi)));
  const dvec3 eye(-6 * std::cos(phi) * std::sin(theta), 6 * std::sin(phi), -6 * std::cos(phi) * std::cos(theta));
  return {eye, ry * rx * ray};
}

// The largest difference between the camera's rays and lee's shader's over a grid of pixels (centres: marchcheck's
// pixel (x, y) is the shader's (x + 0.5, height - y - 0.5)).
double lee_ray_difference(const sdf::CameraSpec& camera, double yaw) {
  const int w = 640, h = 360;
  const Camera cam(camera, w, h);
  double worst = 0;
  for (int y = 0; y < h; y += 37)
    for (int x = 0; x < w; x += 53) {
      const Ray mine = cam.ray(x + 0.5, y + 0.5);
      const Ray theirs = lee_shader_ray(x + 0.5, h - y - 0.5, w, h, yaw, 0.3);
      worst = std::max({worst, glm::length(mine.origin - theirs.origin), glm::length(mine.direction - theirs.direction)});
    }
  return worst;
}

// Double arithmetic in another order: agreement to 1e-12 is rounding; a mirrored image, an inverted lens or an eye
// on the other side is off by 0.1 or more. Broken variants: the look-at camera's axes (world +x on the left), the
// OpenCV lens (the ray through the undistorted point), an orbit whose eye sits on +z at yaw 0.
TEST(SeedScenes, LeeCameraIsItsShadersRayTurnedByRyRx) {
  sdf::CameraSpec camera = sdf::builtin_scene("lee-flat").camera;
  EXPECT_LT(lee_ray_difference(camera, 0), 1e-12);
  camera.yaw_deg = 40;
  EXPECT_LT(lee_ray_difference(camera, 40 * std::numbers::pi / 180), 1e-12);
  EXPECT_LT(Camera(camera, 640, 360).eye().z, 0);  // yaw 40 still sees the sphere from -z
  sdf::CameraSpec mirrored = sdf::builtin_scene("lee-flat").camera, inverse_lens = mirrored;
  mirrored.axes = sdf::CameraAxes::right_handed;
  inverse_lens.lens = sdf::LensConvention::opencv;
  EXPECT_GT(lee_ray_difference(mirrored, 0), 0.01);
  EXPECT_GT(lee_ray_difference(inverse_lens, 0), 0.01);
}

// The forward distortion widens the image: the original's horizontal field of view at 640 px is 60.0 degrees,
// against the pinhole's 56.1 and the inverse lens's 52.8. Between the outermost pixel centres, 319.5 px from the
// centre at f = 600: 2 atan(0.5325 (1 + 0.3 0.5325^2)) forward, 2 atan(0.5325) without the lens.
TEST(SeedScenes, LeeLensWidensTheImageToSixtyDegrees) {
  const auto horizontal_fov = [](const sdf::CameraSpec& c) {
    const Camera cam(c, 640, 360);
    const double cosine = glm::dot(cam.ray(0.5, 180).direction, cam.ray(639.5, 180).direction);
    return std::acos(cosine) * 180 / std::numbers::pi;
  };
  const double x = 319.5 / 600, degrees = 360 / std::numbers::pi;
  sdf::CameraSpec camera = sdf::builtin_scene("lee-flat").camera;
  EXPECT_NEAR(horizontal_fov(camera), std::atan(x * (1 + 0.3 * x * x)) * degrees, 1e-9);
  EXPECT_NEAR(horizontal_fov(camera), 60.0, 0.1);
  camera.lens = sdf::LensConvention::opencv;
  EXPECT_NEAR(horizontal_fov(camera), 52.8, 0.1);
  camera.k1 = 0;
  EXPECT_NEAR(horizontal_fov(camera), std::atan(x) * degrees, 1e-9);
}

// fogerty's ray is exactly normalize(u aspect, v, 1) from (0, 0, -10), u and v in [-1, 1] across the image (v up),
// so world +x is on the image's right. Broken variant: the look-at camera (its mirror image).
TEST(SeedScenes, FogertyRayIsNormalizeUAspectV1) {
  const sdf::Scene s = sdf::builtin_scene("fogerty");
  const int w = 640, h = 360;
  const Camera cam(s.camera, w, h);
  double worst = 0;
  for (int y = 0; y < h; y += 29)
    for (int x = 0; x < w; x += 31) {
      const double u = 2 * (x + 0.5) / w - 1, v = 2 * (h - y - 0.5) / h - 1;
      const Ray r = cam.ray(x + 0.5, y + 0.5);
      worst = std::max({worst, glm::length(r.direction - glm::normalize(dvec3(u * w / h, v, 1))),
                        glm::length(r.origin - dvec3(0, 0, -10))});
    }
  EXPECT_LT(worst, 1e-12);
}

// fogerty's light at (mix(-1.5, 1.5, sin(t)/2 + 1/2), 3 + mix(-1.5, 1.5, sin(1.3 t)/2 + 1/2), -10): (0, 3, -10) at
// t = 0. Broken variant: one rate for both axes (or the old cosine swing, (0, 4.5, -10) at t = 0).
TEST(SeedScenes, FogertyLightFollowsItsPath) {
  const sdf::Light light = sdf::builtin_scene("fogerty").lights.at(0);
  const auto seed = [](double t) {
    return dvec3(glm::mix(-1.5, 1.5, std::sin(t) / 2 + 0.5), 3 + glm::mix(-1.5, 1.5, std::sin(1.3 * t) / 2 + 0.5), -10);
  };
  for (const double t : {0.0, 1.0, 2.5, -7.0}) EXPECT_LT(glm::length(light.position_at(t) - seed(t)), 1e-14) << t;
}

std::array<float, 3> pixel(const Image& image, int x, int y) {
  const float* p = image.at(x, y);
  return {p[0], p[1], p[2]};
}

double luminance(const Image& image, int x, int y) {
  const auto c = pixel(image, x, y);
  return (c[0] + c[1] + c[2]) / 3.0;
}

// lee at yaw 0 and t = 0: the eye is on -z and the light (0, 5, 6) behind the sphere, so the sphere's visible side
// is dark (lit only at its rim) against the lit ground, and its shadow falls toward the camera (below the sphere
// in the image, not behind it). Measured at 320x180: the sphere's mean 0.03, the ground's 0.19; the eye put on +z
// (the rebuild before) lights the sphere's visible side (mean 0.35).
TEST(SeedScenes, LeeSphereIsDarkAgainstTheLitGroundAndItsShadowComesTowardTheCamera) {
  sdf::Scene s = sdf::builtin_scene("lee-flat");
  s.width = 320, s.height = 180;
  s.camera.fx = s.camera.fy = 150;
  EXPECT_LT(Camera(s.camera, s.width, s.height).eye().z, 0);
  const RenderResult r = render(s, {Aov::id});
  double sphere = 0, ground = 0;
  int n_sphere = 0, n_ground = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const float id = *r.id.at(x, y);
      if (id == 0) sphere += luminance(r.color, x, y), ++n_sphere;
      if (id == 1) ground += luminance(r.color, x, y), ++n_ground;
    }
  ASSERT_GT(n_sphere, 1000);
  ASSERT_GT(n_ground, 1000);
  EXPECT_LT(sphere / n_sphere, 0.3 * (ground / n_ground));
  // The shadow falls toward the camera: the ground just below the sphere's image is darker than the same pixel
  // with shadows off (diffuse kept at 0.3; measured 0.06 against 0.22).
  int below = -1;
  for (int y = s.height - 1; y >= 0 && below < 0; --y)
    if (*r.id.at(s.width / 2, y) == 0) below = y + 1;  // the first ground row under the sphere
  ASSERT_GT(below, 0);
  sdf::Scene unshadowed = s;
  unshadowed.lights[0].shadow = sdf::ShadowMode::none;
  const RenderResult lit = render(unshadowed);
  const int row = std::min(s.height - 1, below + 8);
  EXPECT_LT(luminance(r.color, s.width / 2, row), 0.5 * luminance(lit.color, s.width / 2, row));
}

// lee adds its specular whether or not the point is in shadow: against a scene that removes it in shadow, the
// difference is there (shadowed ground and sphere pixels, up to about 13/255 in the original) and nowhere else.
// Broken variant: the specular multiplied by the shadow's visibility.
TEST(SeedScenes, LeeSpecularStaysInShadow) {
  sdf::Scene s = sdf::builtin_scene("lee-flat");
  s.width = 320, s.height = 180;
  s.camera.fx = s.camera.fy = 150;
  sdf::Scene removed = s;
  removed.lights[0].specular_in_shadow = false;
  sdf::Scene unshadowed = s;
  unshadowed.lights[0].shadow = sdf::ShadowMode::none;
  const RenderResult a = render(s), b = render(removed), lit = render(unshadowed);
  double largest = 0;
  int differing = 0, outside_shadow = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      // In shadow: where the shadow changes the scene that lets it take the specular away.
      const bool shadowed = pixel(b.color, x, y) != pixel(lit.color, x, y);
      const auto pa = pixel(a.color, x, y), pb = pixel(b.color, x, y);
      const double d = std::max({pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]});
      largest = std::max(largest, d);
      differing += d > 0;
      outside_shadow += d > 0 && !shadowed;
    }
  EXPECT_GT(differing, 100);
  EXPECT_GT(largest, 3.0 / 255);
  EXPECT_LT(largest, 20.0 / 255);
  EXPECT_EQ(outside_shadow, 0);
}

// fogerty's Phong highlight (reflect(-l, n) . to_camera, exponent 4, in 4 bands capped by the diffuse band): its
// top band is 20 rows tall at 640x360 in the original; Blinn's half vector, which the rebuild used, made it 39.
// The top band is white at 1 over the red (0.1 everywhere on the sphere, then 0.4, 0.7, 1): green above 0.8 where
// red is above green (the grey background has them equal). The tolerance, 1 row, is the band edge's rounding.
// Broken variant: Blinn.
TEST(SeedScenes, FogertyHighlightIsPhongs) {
  sdf::Scene s = sdf::builtin_scene("fogerty");
  s.width = 640, s.height = 360;
  const auto highlight_rows = [](const sdf::Scene& scene) {
    const RenderResult r = render(scene);
    std::set<int> rows;
    for (int y = 0; y < scene.height; ++y)
      for (int x = 0; x < scene.width; ++x)
        if (pixel(r.color, x, y)[1] > 0.8 && pixel(r.color, x, y)[0] > pixel(r.color, x, y)[1] + 0.05) rows.insert(y);
    return static_cast<int>(rows.size());
  };
  const int phong = highlight_rows(s);
  EXPECT_NEAR(phong, 20, 1);
  s.materials[0].specular = sdf::SpecularModel::blinn;
  EXPECT_GT(highlight_rows(s), phong + 10);
}

// fogerty's bands are mix(0.1, 1, mod(floor(4 d), 4) / 3): d = 1 exactly falls in the lowest band. On an odd-sized
// image the centre ray is (0, 0, 1) exactly, meets the sphere on its axis, and central differences give the normal
// (0, 0, -1) exactly; a light shining along +z makes d = 1 there, so the centre pixel's red is 0.1 + 0.1 (lowest
// diffuse and specular bands) while its neighbours (d just below 1) are in the top band. Broken variant: d = 1
// clamped into the top band.
TEST(SeedScenes, FogertyPutsAFullyLitPointInTheLowestBand) {
  sdf::Scene s = sdf::builtin_scene("fogerty");
  s.width = s.height = 33;
  s.camera.fov_deg = 40;
  sdf::Light light;
  light.type = sdf::LightType::directional;
  light.direction = {0, 0, 1};
  s.lights = {light};
  const RenderResult r = render(s);
  EXPECT_NEAR(pixel(r.color, 16, 16)[0], 0.2, 1e-6);
  EXPECT_GT(pixel(r.color, 17, 16)[0], 1.5);
}

// lee-textured's sphere texture is measured about the sphere's centre (texture_origin): the whole scene moved by
// (5, 0, 10) (a whole period of the ground's fract(0.2 p.xz)) draws the same sphere. Colours agree to 0.02: the
// march rounds differently at the new coordinates (hits move by ~1e-6, far below a texel). Broken variant: the
// angles measured about the world origin.
TEST(SeedScenes, LeeSphereTextureTurnsAboutTheSpheresCentre) {
  sdf::Scene s = sdf::builtin_scene("lee-textured");
  s.width = 160, s.height = 90;
  s.camera.fx = s.camera.fy = 75;
  const RenderResult a = render(s, {Aov::id}), b = render(sdf::moved_by(s, {5, 0, 10}), {Aov::id});
  double worst = 0;
  int sphere = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      if (*a.id.at(x, y) != 0 || *b.id.at(x, y) != 0) continue;
      ++sphere;
      for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(a.color.at(x, y)[c] - b.color.at(x, y)[c])));
    }
  EXPECT_GT(sphere, 300);  // 500 at this size
  EXPECT_LT(worst, 0.02);
}

// fogerty's 32 steps leave the rays that graze the sphere unfinished, and the seed shades any t > 0: they are drawn
// where they stopped, in the black silhouette, a rim about 2 px wide around the disc (118 px across at 640x360 in
// the original, 110 where they were drawn as background). Across the middle row the defect's disc is 118 px wide
// against the fixed scene's 114, and what it adds is black. Broken variant: unfinished rays read as misses.
TEST(SeedScenes, FogertyStepsDefectHasABlackRim) {
  const auto disc = [](const std::string& name) {
    sdf::Scene s = sdf::builtin_scene(name);
    s.width = 640, s.height = 360;
    const RenderResult r = render(s);
    std::vector<std::array<float, 3>> row;
    for (int x = 0; x < s.width; ++x)
      if (pixel(r.color, x, 180) != std::array<float, 3>{0.7f, 0.7f, 0.7f}) row.push_back(pixel(r.color, x, 180));
    return row;
  };
  const auto fixed = disc("fogerty"), defect = disc("fogerty-defect-steps");
  EXPECT_EQ(defect.size(), 118u);
  EXPECT_GE(defect.size(), fixed.size() + 2);
  const auto black = [](const std::array<float, 3>& c) { return c[0] == 0 && c[1] == 0 && c[2] == 0; };
  EXPECT_TRUE(black(defect.front()) && black(defect.back()));
}

// fogerty's mediump: in binary16 the normal's 1e-3 offsets round away at |p| near 3 (values there lie 2^-9 apart)
// and hits land on a 2^-9 grid, so the toon bands break into speckle: counted as pixels whose colour differs from
// all four neighbours (a band edge is one-sided). At 640x360 the fixed scene, in float, has 16 (band corners), the
// variant 2282 of the disc's ~10 000 pixels; the limits sit a factor of two or more from both. Broken variant: the
// tape's half flag ignored (sdf-half-tape-in-float).
TEST(SeedScenes, FogertyMediumpIsSpeckled) {
  const auto speckles = [](const std::string& name) {
    sdf::Scene s = sdf::builtin_scene(name);
    s.width = 640, s.height = 360;
    const RenderResult r = render(s);
    int count = 0;
    for (int y = 1; y + 1 < s.height; ++y)
      for (int x = 1; x + 1 < s.width; ++x) {
        const auto c = pixel(r.color, x, y);
        count += c != pixel(r.color, x - 1, y) && c != pixel(r.color, x + 1, y) && c != pixel(r.color, x, y - 1) &&
                 c != pixel(r.color, x, y + 1);
      }
    return count;
  };
  EXPECT_EQ(sdf::builtin_scene("fogerty-defect-mediump").march.precision, sdf::Precision::float16);
  const int fixed = speckles("fogerty"), mediump = speckles("fogerty-defect-mediump");
  EXPECT_LT(fixed, 40) << fixed;
  EXPECT_GT(mediump, 1000) << mediump;
}

// A material's own image: a ground textured with a 4x4 image of one colour (EXR, so exactly that colour; a one-
// channel image reads as grey) draws that colour where ambient light alone shows the albedo. Broken variant: the
// soil sampled whatever the material names.
TEST(SeedScenes, AMaterialsTextureFileIsWhatItDraws) {
  const auto folder = std::filesystem::temp_directory_path() / ("marchcheck_texture_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  Image rgb(4, 4, 3), grey(4, 4, 1);
  for (int i = 0; i < 16; ++i) {
    rgb.pixels[static_cast<size_t>(3 * i)] = 0.2f, rgb.pixels[static_cast<size_t>(3 * i + 1)] = 0.4f;
    rgb.pixels[static_cast<size_t>(3 * i + 2)] = 0.6f, grey.pixels[static_cast<size_t>(i)] = 0.3f;
  }
  write_image(rgb, (folder / "rgb.exr").string());
  write_image(grey, (folder / "grey.exr").string());
  for (const auto& [file, expected] : {std::pair{"rgb.exr", std::array<float, 3>{0.2f, 0.4f, 0.6f}},
                                       std::pair{"grey.exr", std::array<float, 3>{0.3f, 0.3f, 0.3f}}}) {
    sdf::Scene s = sdf::builtin_scene("lee-textured");
    s.width = 32, s.height = 18;
    s.camera.fx = s.camera.fy = 15;
    s.lights.clear();
    s.effects.ambient = 1;
    s.materials[1].texture_file = (folder / file).string();
    const RenderResult r = render(s, {Aov::id});
    int ground = 0;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x)
        if (*r.id.at(x, y) == 1) {
          ++ground;
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.color.at(x, y)[c], expected[c], 1e-6) << file;
        }
    EXPECT_GT(ground, 50) << file;
  }
  std::filesystem::remove_all(folder);
}

// lee's miss returns +inf and its shader shades it anyway at ro + inf rd: every background pixel of the variant that
// reproduces it is NaN, and its PNG writes them black, as llvmpipe does; every other pixel is the fixed scene's.
// Broken variants: misses left as misses; NaN written as whatever the conversion makes of it.
TEST(SeedScenes, LeesShadedMissIsNaNWrittenBlack) {
  sdf::Scene fixed = sdf::builtin_scene("lee-flat"), defect = sdf::builtin_scene("lee-flat-defect-nan");
  for (sdf::Scene* s : {&fixed, &defect}) {
    s->width = 160, s->height = 90;
    s->camera.fx = s->camera.fy = 75;
  }
  const RenderResult a = render(fixed, {Aov::id}), b = render(defect);
  int misses = 0, nan = 0, other = 0;
  for (int y = 0; y < fixed.height; ++y)
    for (int x = 0; x < fixed.width; ++x) {
      const bool miss = *a.id.at(x, y) < 0;
      misses += miss;
      const auto c = pixel(b.color, x, y);
      if (miss) nan += std::isnan(c[0]) && std::isnan(c[1]) && std::isnan(c[2]);
      if (!miss) other += c != pixel(a.color, x, y);
    }
  EXPECT_GT(misses, 100);
  EXPECT_EQ(nan, misses);
  EXPECT_EQ(other, 0);
  Image one(1, 1, 3, std::numeric_limits<float>::quiet_NaN());
  EXPECT_EQ(to_8bit(one, false), (Bytes{0, 0, 0}));
  EXPECT_EQ(to_8bit(one, true), (Bytes{0, 0, 0}));
  // Its error (validate's difference image holds +inf there) shows at the top of the heat map, not the bottom.
  const Image infinite(1, 1, 1, std::numeric_limits<float>::infinity());
  EXPECT_EQ(pixel(heat_map(infinite, kErrorHeatMapMax), 0, 0), (std::array<float, 3>{0.98f, 0.98f, 0.65f}));
}

// crum-torus's listing draws no glow: every pixel that is not a hit is exactly black. Broken variant: the glow on.
TEST(SeedScenes, CrumTorusMissesAreExactlyBlack) {
  sdf::Scene s = sdf::builtin_scene("crum-torus");
  s.width = 160, s.height = 90;
  const RenderResult r = render(s);
  int misses = 0, lit_misses = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      if (static_cast<Outcome>(*r.outcome.at(x, y)) == Outcome::hit) continue;
      ++misses;
      const auto c = pixel(r.color, x, y);
      lit_misses += c[0] != 0 || c[1] != 0 || c[2] != 0;
    }
  EXPECT_GT(misses, 1000);
  EXPECT_EQ(lit_misses, 0);
}

// The shaders write their values into an 8-bit framebuffer as they are: fogerty's grey 0.7 is 179 there (sRGB
// would make it 218). The seed scenes declare it; the others (meshes) keep sRGB.
TEST(SeedScenes, SeedsWriteTheirValuesAsTheyAre) {
  for (const char* name : {"lee-flat", "lee-terrain", "fogerty", "crum-torus", "warped"})
    EXPECT_EQ(sdf::builtin_scene(name).output_transfer, sdf::OutputTransfer::linear) << name;
  EXPECT_EQ(sdf::builtin_scene("mesh-box").output_transfer, sdf::OutputTransfer::srgb);
  sdf::Scene s = sdf::builtin_scene("fogerty");
  s.width = 32, s.height = 18;
  const RenderResult r = render(s);
  EXPECT_EQ(r.transfer, sdf::OutputTransfer::linear);
  Image corner(1, 1, 3);
  std::copy_n(r.color.at(0, 0), 3, corner.at(0, 0));
  EXPECT_EQ(to_8bit(corner, r.transfer == sdf::OutputTransfer::srgb), (Bytes{179, 179, 179}));
  EXPECT_EQ(to_8bit(corner, true), (Bytes{218, 218, 218}));
}

}  // namespace
}  // namespace marchcheck::march
