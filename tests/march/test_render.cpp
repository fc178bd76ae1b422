// The renderer: deterministic on any thread count, identical for a scene and its file, Lambert where it must be.
#include "marchcheck/march/render.hpp"
#include "marchcheck/march/tolerances.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/scene_file.hpp"

#include "builtin_param.hpp"
#include "mapped_block.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <fstream>
#include <cstdio>
#include <cinttypes>
#include <filesystem>
#include <numeric>
#include <optional>

namespace marchcheck::march {
namespace {

sdf::Scene small(const std::string& name, int w = 96, int h = 54) {
  sdf::Scene s = sdf::builtin_scene(name);
  s.width = w;
  s.height = h;
  return s;
}

TEST(Render, SameImageAndCountsOnOneThreadAndOnAll) {
  const sdf::Scene scene = small("lee-terrain");
  RenderResult one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = render(scene);
  }
  const RenderResult all = render(scene);
  EXPECT_EQ(one.color.pixels, all.color.pixels);
  EXPECT_EQ(one.evals.pixels, all.evals.pixels);
  EXPECT_EQ(one.total_evals, all.total_evals);
}

// After a render, join_render_workers leaves the process its one thread: no worker is left to wind down during
// exit, where one crashed LeakSanitizer's exit-time tracer in CI. On one core TBB starts no worker and this holds
// trivially. Broken variant: a join that returns true without finalizing TBB leaves its workers running.
TEST(Render, JoinRenderWorkersLeavesTheProcessOneThread) {
  const auto threads = [] {
    const std::filesystem::directory_iterator tasks("/proc/self/task");
    return std::distance(begin(tasks), end(tasks));
  };
  render(small("lee-flat", 64, 64));
  ASSERT_TRUE(join_render_workers());
  EXPECT_EQ(threads(), 1);
  EXPECT_GT(render(small("lee-flat", 8, 4)).total_evals, 0) << "a render after the join starts workers anew";
}

// An image made with a fill value holds it in every sample, below 2 MiB (the plain allocation) and above (the
// aligned one). Broken variant: the value ignored, every sample 0 (march-image-fill-ignored).
TEST(Render, AnImageIsFilledWithItsValue) {
  for (const int width : {4, 1280}) {
    const Image image(width, 720, 3, 0.25f);
    EXPECT_EQ(std::count(image.pixels.begin(), image.pixels.end(), 0.25f), static_cast<long>(image.pixels.size()))
        << width << "x720";
  }
}

// A large image lies on 2 MiB pages where the kernel allows them on request (transparent huge pages "madvise" or
// "always"): lee-flat's 1280x720 colour image (10.5 MiB) starts on a 2 MiB boundary, so that no unaligned head is
// left on 4 KiB pages, and the mapping holding it has at least two huge pages (smaps' AnonHugePages) right after it
// was made. The huge pages are skipped where the kernel has them off. Broken variants: the advice not given
// (march-no-huge-pages); the block aligned to a cache line only (march-pixels-unaligned).
TEST(Render, ALargeImageLiesOnHugePages) {
  const Image image(1280, 720, 3);
  const auto start = reinterpret_cast<std::uintptr_t>(image.pixels.data());
  EXPECT_EQ(start % (std::uintptr_t(2) << 20), 0u);
  std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
  const std::string mode((std::istreambuf_iterator<char>(mode_file)), {});
  if (mode.find("[never]") != std::string::npos || mode.empty()) GTEST_SKIP() << "transparent huge pages are off";
  const auto at = start + image.pixels.size() * sizeof(float) / 2;
  std::ifstream smaps("/proc/self/smaps");
  long huge_kib = -1;
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t lo = 0, hi = 0;
    if (std::sscanf(line.c_str(), "%" SCNxPTR "-%" SCNxPTR " ", &lo, &hi) == 2 && line.find(':') > line.find(' '))
      inside = lo <= at && at < hi;
    else if (inside && line.starts_with("AnonHugePages:"))
      huge_kib = std::stol(line.substr(14));
  }
  EXPECT_GE(huge_kib, 4096) << "no huge page under the image's mapping (mode: " << mode << ")";
  EXPECT_EQ(image.pixels[image.pixels.size() / 2], 0.0f);
}

// After keep_freed_memory a block as large as a big render's image (24 MiB) comes from the heap and stays there
// when freed, for the next render to reuse without faulting its pages in again. In a fresh process (ctest runs each
// test in its own) glibc would map it on its own (mallinfo2's hblks) and hand it back when freed. Skipped under
// AddressSanitizer, whose allocator replaces glibc's. Broken variants: nothing set (march-freed-memory-mapped), the
// heap trimmed as before (march-freed-memory-trimmed).
TEST(Render, FreedMemoryStaysForTheNextRender) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's allocator replaces glibc's";
#endif
  keep_freed_memory();
  constexpr std::size_t kBlock = std::size_t(24) << 20;
  EXPECT_FALSE(testing::mapped_on_its_own(kBlock));
  EXPECT_GE(mallinfo2().fordblks, kBlock) << "the freed block left the heap";
}

// Renders one after another in a process (a sweep, a benchmark) reuse the heap the last one freed: after the
// second render of lee-flat at 1280x720, four more grow glibc's heap (mallinfo2's arena) by less than one 2 MiB
// huge page, the slack for small blocks that land between. Aligning each large image with glibc's own aligned
// allocation grew it by 7 MiB a render here (a loop of 40 lee-flat renders peaked at 230 MB instead of 45 MB), every
// image on fresh pages, whose zeroing by the kernel was 9% of a profile of warm renders. Skipped under
// AddressSanitizer, whose allocator replaces glibc's. Broken variants: the image aligned by the allocator
// (march-pixels-aligned-new); freed at its aligned start, not where its allocation began (march-pixels-free-aligned,
// which glibc aborts on).
TEST(Render, RendersInARowReuseTheHeap) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's allocator replaces glibc's";
#endif
  keep_freed_memory();
  const sdf::Scene scene = small("lee-flat", 1280, 720);
  RenderResult last;  // each render is made while the last one is still held, as a loop that keeps it does
  for (int i = 0; i < 2; ++i) last = render(scene, {}, nullptr, Images::asked);
  const std::size_t heap = mallinfo2().arena;
  for (int i = 0; i < 4; ++i) last = render(scene, {}, nullptr, Images::asked);
  EXPECT_LT(mallinfo2().arena, heap + (std::size_t(2) << 20)) << "heap after two renders: " << heap << " bytes";
}

// march makes no reference render: the error AOV is written from the difference its caller passes, and asking
// for it without one is an error rather than a missing file.
TEST(Render, TheErrorAovNeedsItsDifferenceImage) {
  EXPECT_EQ(parse_aovs("steps,error"), (std::vector<Aov>{Aov::steps, Aov::error}));
  const RenderResult r = render(small("lee-flat", 8, 4));
  const std::string path = (std::filesystem::temp_directory_path() / "marchcheck-error-aov.png").string();
  EXPECT_THROW(write_render(r, path, {Aov::error}), std::invalid_argument);
  const Image difference(8, 4, 1, 0.1f);
  write_render(r, path, {Aov::error}, &difference);
  const std::string written = (std::filesystem::temp_directory_path() / "marchcheck-error-aov.error.png").string();
  EXPECT_TRUE(std::filesystem::exists(written));
  std::filesystem::remove(path);
  std::filesystem::remove(written);
}

class EveryBuiltin : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryBuiltin, SceneFileRendersTheSameImageBitForBit) {
  const sdf::Scene scene = small(GetParam(), 64, 36);
  const sdf::Scene loaded = sdf::scene_from_json(sdf::scene_to_json(scene), "exported.json");
  const RenderResult a = render(scene), b = render(loaded);
  EXPECT_EQ(a.color.pixels, b.color.pixels);
  EXPECT_EQ(a.total_evals, b.total_evals);
}

// Keeping only the asked-for images changes no pixel and no count: the images left out are merely not written.
// Broken variants: the depth image, asked for alone, never written (march-depth-image-skipped); a thread's most
// steps taken from the last tile it rendered, not from all of them (march-steps-max-last-tile).
TEST_P(EveryBuiltin, KeepingOnlyAskedImagesChangesNothingElse) {
  const sdf::Scene scene = small(GetParam(), 64, 36);
  const RenderResult all = render(scene, {Aov::depth}), asked = render(scene, {Aov::depth}, nullptr, Images::asked);
  EXPECT_EQ(asked.color.pixels, all.color.pixels);
  EXPECT_EQ(asked.depth.pixels, all.depth.pixels);
  EXPECT_EQ(asked.total_evals, all.total_evals);
  for (const Image* left_out : {&asked.normal, &asked.steps, &asked.evals, &asked.stage_evals, &asked.id, &asked.outcome})
    EXPECT_TRUE(left_out->pixels.empty());
  // steps_max stands in for the steps image in cost_metrics.
  EXPECT_EQ(asked.steps_max, static_cast<int>(*std::max_element(all.steps.pixels.begin(), all.steps.pixels.end())));
  EXPECT_EQ(cost_metrics(asked).at("cost.steps_max"), cost_metrics(all).at("cost.steps_max"));
}

// The stages' totals are the sum of the pixels' counts. Broken variant: the packets' shadow evaluations charged to
// the pixels but never booked to the shadow stage (march-shadow-evals-unbooked).
TEST_P(EveryBuiltin, EvaluationCountsAddUpAndNoPixelIsNaN) {
  const RenderResult r = render(small(GetParam(), 64, 36));
  const double per_pixel_sum = std::accumulate(r.evals.pixels.begin(), r.evals.pixels.end(), 0.0);
  EXPECT_EQ(static_cast<std::uint64_t>(per_pixel_sum), r.total_evals);
  std::uint64_t staged = 0;
  for (const auto& [name, cost] : r.stages) staged += cost.evals;
  EXPECT_EQ(staged, r.total_evals);
  // Per stage, the per-pixel channels add up to the stage's total.
  for (size_t stage = 0; stage < r.stage_names.size(); ++stage) {
    double sum = 0;
    for (size_t i = stage; i < r.stage_evals.pixels.size(); i += r.stage_names.size()) sum += r.stage_evals.pixels[i];
    EXPECT_EQ(static_cast<std::uint64_t>(sum), r.stages.at(r.stage_names[stage]).evals) << r.stage_names[stage];
  }
  // No NaN, but in the variant that reproduces the lee seed's NaN background (SeedScenes.LeesShadedMissIsNaN...).
  if (std::ranges::count(sdf::builtin_scene(GetParam()).defects, "nan") > 0) return;
  for (float v : r.color.pixels) ASSERT_FALSE(std::isnan(v));
}

// Float shading draws the 8-bit image that double shading draws, with the same evaluations: no channel moves by
// more than one level, and at most 1e-3 of the channels move at all (only those within float rounding of a
// level boundary: float's ~1e-6 relative error over the shading's few tens of operations is ~3e-4 of a level,
// so ~1e-3 of uniformly spread values at the steepest, 12.92x sRGB slope; all scenes together moved 2 channels in
// 830k when this was written). Caught: float shading 5e-4 brighter than double (an eighth of a level) moves
// 0.4-1.3% of the channels on several scenes.
TEST_P(EveryBuiltin, FloatShadingDrawsTheDoubleShadedEightBitImage) {
  const sdf::Scene scene = small(GetParam(), 128, 72);
  const RenderResult single = render(scene, {}, nullptr, Images::asked, ShadePrecision::float32);
  const RenderResult dual = render(scene, {}, nullptr, Images::asked, ShadePrecision::float64);
  EXPECT_EQ(single.total_evals, dual.total_evals);
  const Bytes a = to_8bit(single.color), b = to_8bit(dual.color);
  ASSERT_EQ(a.size(), b.size());
  int moved = 0, most = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const int d = std::abs(int(a[i]) - int(b[i]));
    moved += d > 0;
    most = std::max(most, d);
  }
  EXPECT_LE(most, 1);
  EXPECT_LE(moved, static_cast<int>(1e-3 * static_cast<double>(a.size()))) << "of " << a.size() << " channels";
}

INSTANTIATE_TEST_SUITE_P(All, EveryBuiltin, ::testing::ValuesIn(sdf::builtin_scene_names()),
                         marchcheck::testing::builtin_param_name);

// A reference render's shadow rays start from the oracle's own double hit, lifted by that hit's error bound, not
// from the float point: a wall at z = 1000.37 (solid behind it) seen from z = -5000, lit along +z from behind a
// screen at z = -6000 that shadows all of it. The float point o + d t rounds with |o| + t = 11000 and can lie
// inside the wall by more than the float lift at |p| = 1000 (counted below: the fixture makes such points); a ray
// starting inside the solid finds no surface, so it counted as lit. Broken variant: shadow rays from the float
// point (speckles of light in the shadow).
TEST(Render, ReferenceShadowRaysStartFromTheReferencesOwnHit) {
  constexpr double kWall = 1000.37;
  sdf::Scene s;
  s.name = "wall";
  s.materials = {{"white", glm::dvec3(1)}};
  s.root = sdf::sphere(1, 0);  // never marched: the oracle gives every surface
  s.width = s.height = 64;
  s.camera.position = {0, 0, -5000};
  s.camera.target = {0, 0, 0};
  s.camera.fov_deg = 10;
  s.march.max_dist = 1e5;
  s.effects.ambient = 0.1;
  sdf::Light light;
  light.type = sdf::LightType::directional;
  light.direction = {0, 0, 1};
  light.shadow = sdf::ShadowMode::hard;
  s.lights = {light};
  const SurfaceOracle oracle{[&](glm::dvec3 o, glm::dvec3 d, double t_max) -> std::optional<SurfaceOracle::Hit> {
    if (o.z >= kWall) return std::nullopt;  // inside the wall's solid: a reference finds no first surface
    if (d.z > 0 && (kWall - o.z) / d.z <= t_max) return SurfaceOracle::Hit{(kWall - o.z) / d.z, {0, 0, -1}};
    if (d.z < 0 && o.z > -6000 && (o.z + 6000) / -d.z <= t_max)
      return SurfaceOracle::Hit{(o.z + 6000) / -d.z, {0, 0, 1}};
    return std::nullopt;
  }};
  const RenderResult r = render(s, {}, &oracle);
  const Camera cam(s.camera, s.width, s.height);
  int deep = 0, lit = 0, hit = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const Ray ray = cam.ray(x + 0.5, y + 0.5);
      const glm::dvec3 d = glm::normalize(ray.direction);
      const glm::vec3 p = glm::vec3(ray.origin) + glm::vec3(d) * static_cast<float>((kWall - ray.origin.z) / d.z);
      deep += p.z - kWall > tolerance::shadow_lift(glm::dvec3(p));
      // Ambient 0.1 in shadow, 0.1 + n.l (about 1) lit.
      lit += r.color.at(x, y)[0] > 0.5f;
      hit += r.color.at(x, y)[0] > 0.05f;  // not the black background
    }
  EXPECT_EQ(hit, s.width * s.height) << "every pixel sees the wall";
  EXPECT_GT(deep, 0) << "the fixture no longer puts float points deeper than the float lift";
  EXPECT_EQ(lit, 0) << "of " << s.width * s.height << " pixels, all in the plane's shadow";
}

TEST(Render, LambertAndPhongOnASphereEqualTheClosedForm) {
  sdf::Scene s;
  s.name = "lambert";
  s.materials = {{"white", glm::dvec3(1)}};
  s.root = sdf::sphere(1, 0);
  s.width = s.height = 101;
  s.camera.position = {0, 0, 5};
  s.camera.target = {0, 0, 0};
  s.camera.fov_deg = 40;
  s.effects.ambient = 0.1;
  sdf::Light light;
  light.type = sdf::LightType::directional;
  light.direction = glm::normalize(glm::dvec3(-1, -1, -1));
  s.lights = {light};
  s.materials[0].specular = sdf::SpecularModel::phong;
  s.materials[0].specular_strength = 0.3;
  s.materials[0].shininess = 10;
  s.march.hit_eps = 1e-9;
  s.march.max_steps = 100000;  // near-tangent hits converge slowly at this eps
  s.march.normal_eps = 1e-5;
  s.march.precision = sdf::Precision::float64;  // the shading formula is under test here, not float rounding
  const RenderResult r = render(s, {}, nullptr, Images::all, ShadePrecision::float64);
  const Camera cam(s.camera, s.width, s.height);
  int checked = 0;
  for (int y = 0; y < s.height; y += 10)
    for (int x = 0; x < s.width; x += 10) {
      const Ray ray = cam.ray(x + 0.5, y + 0.5);
      // Closed-form ray-sphere intersection.
      const double b = glm::dot(ray.origin, ray.direction), c = glm::dot(ray.origin, ray.origin) - 1;
      const double disc = b * b - c;
      if (disc < 1e-3) continue;  // skip silhouettes, where hit_eps decides hit or miss
      const glm::dvec3 n = ray.origin + ray.direction * (-b - std::sqrt(disc));
      // Ambient + Lambert + Phong: 0.3 clamp(dot(reflect(-l, n), to_eye))^10 (Lee's sphere).
      const glm::dvec3 l = -light.direction, to_eye = glm::normalize(ray.origin - n);
      const double phong = 0.3 * std::pow(std::clamp(glm::dot(glm::reflect(-l, n), to_eye), 0.0, 1.0), 10.0);
      const double expected = 0.1 + std::clamp(glm::dot(n, l), 0.0, 1.0) + phong;
      // Double march to 1e-9 and central normals at 1e-5 (truncation ~1e-10): the colour is stored as float,
      // so its own rounding (6e-8 relative) dominates.
      EXPECT_NEAR(r.color.at(x, y)[0], expected, 1e-6) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 20);
}

TEST(Render, TimeMovesAnimatedScenesAndLights) {
  for (const char* name : {"warped", "flafla-animated", "lee-flat"}) {
    sdf::Scene a = small(name), b = small(name);
    a.time = 0.5;
    b.time = 2.0;
    EXPECT_NE(render(a).color.pixels, render(b).color.pixels) << name;
  }
}

TEST(Render, WritesEveryOutputAtomically) {
  const auto dir = std::filesystem::temp_directory_path() / "marchcheck_render_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const RenderResult r = render(small("crum-torus"));
  write_render(r, (dir / "torus.png").string(), parse_aovs("depth,normal,steps,evals,id,stages"));
  write_image(r.color, (dir / "torus.exr").string());
  for (const char* f : {"torus.png", "torus.exr", "torus.depth.exr", "torus.normal.png", "torus.steps.png",
                        "torus.evals.png", "torus.id.png", "torus.evals-march.png", "torus.evals-normal.png"})
    EXPECT_GT(std::filesystem::file_size(dir / f), 0u) << f;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  EXPECT_THROW(write_image(r.color, (dir / "torus.unknown-format").string()), std::runtime_error);
  EXPECT_THROW(parse_aovs("depth,colour"), std::invalid_argument);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace marchcheck::march
