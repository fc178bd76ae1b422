// Every built-in's Shadertoy export rendered on the GL driver beside marchcheck's own render, pixel by pixel, with
// validate's image rule: a pixel differs when a colour channel differs by more than 0.1 (here in the sRGB both
// images show), and at most 2% may (image.pixels_over's default limit); on llvmpipe the built-ins that do not turn
// on its transcendentals, and the settings no built-in uses (rendered as variants), are held closer (kLevel).
// Skips without a driver. Every export renders finite pixels. Broken variants: tests/mutants/sdf-export-* (the
// camera's rows counted from the bottom, a light without its colour, each effect dropped or computed otherwise).
#include "marchcheck/gpu/user_marcher.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/march/texture.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/glsl_export.hpp"
#include "marchcheck/sdf/glsl_field.hpp"
#include "srgb.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

namespace marchcheck {
namespace {

using testing::to_srgb;

// The fractions of pixels where the export rendered on the driver and marchcheck's render differ by more than
// `levels` (0 to 1 as written: sRGB, or the values as they are), one for each.
std::vector<double> pixels_over(const sdf::Scene& scene, const std::vector<float>& levels) {
  const int w = scene.width, h = scene.height;
  // The bound: llvmpipe compiles mesh-icosphere's export in about 130 s without its shader cache (the mesh walk is
  // written out without loops, and the map is inlined wherever it is called); it renders in about 15 s.
  const std::vector<float> driver =
      gpu::render_shadertoy(sdf::shadertoy_shader(scene), scene.name + ".glsl", w, h, 400);
  // llvmpipe computes mediump in float (a precision qualifier is a minimum): a half scene's export is its float.
  sdf::Scene on_cpu = scene;
  if (on_cpu.march.precision == sdf::Precision::float16) on_cpu.march.precision = sdf::Precision::float32;
  const march::RenderResult cpu = march::render(on_cpu, {}, nullptr, march::Images::asked);
  std::vector<double> over(levels.size(), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* c = cpu.color.at(x, y);
      const float* d = &driver[(static_cast<size_t>(h - 1 - y) * w + x) * 4];  // Shadertoy's rows count up
      // A NaN pixel (the lee seed's shaded miss) is undefined: a driver writes it as it likes.
      if (std::isnan(c[0]) || std::isnan(c[1]) || std::isnan(c[2])) continue;
      float largest = 0;
      for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(std::isfinite(d[k])) << scene.name << " pixel " << x << ", " << y;
        const float written = scene.output_transfer == sdf::OutputTransfer::srgb ? to_srgb(c[k]) : std::clamp(c[k], 0.0f, 1.0f);
        largest = std::max(largest, std::abs(written - d[k]));
      }
      for (size_t i = 0; i < levels.size(); ++i) over[i] += largest > levels[i];
    }
  for (double& o : over) o /= w * h;
  return over;
}

constexpr float kValidateLevel = 0.1f;      // image.pixels_over's channel difference
constexpr double kValidateFraction = 0.02;  // and its default limit
// One 8-bit level and a half: the export computes what the renderer computes in float, operation for operation,
// but for the driver's own dot, normalize, cross and pow; on these smooth scenes at most one pixel of 14 400
// differs by more on llvmpipe (measured), so 0.1% is the limit there. A GPU's transcendentals are its own: there
// validate's rule alone holds.
constexpr float kLevel = 1.5f / 255;
constexpr double kLevelFraction = 0.001;

// Mesa's software driver, IEEE arithmetic throughout: the one where kLevel holds.
bool on_llvmpipe() { return gpu::driver_renderer().find("llvmpipe") != std::string::npos; }

void skip_without_driver() {
  try {
    gpu::driver_renderer();
  } catch (const gpu::DriverUnavailable& e) {
    GTEST_SKIP() << "no GL driver: " << e.what();
  }
}

// Built-ins whose pixels turn on the driver's own transcendentals, so that more than 0.1% of them move by more
// than one level on llvmpipe too (measured at 160 px: crum-mandelbulb 2.8%, its pow at every iteration;
// crum-lattice 0.28% and its defect 0.63%, edges of a thousand bars; lee-terrain-defect-hash 0.08%, near the limit,
// the seed's sin hash). Of every other built-in at most 2 pixels in 14 400 differ by more there (crum-torus).
bool on_the_drivers_transcendentals(const std::string& name) {
  return name == "crum-mandelbulb" || name == "crum-lattice" || name == "crum-lattice-defect-lipschitz" ||
         name == "lee-terrain-defect-hash";
}

// Validate's rule for every built-in and, on llvmpipe, one level for the rest: at validate's rule alone the glass
// sphere's refraction with the index ratio inverted passed (1.9% of lee-glass's pixels, sdf-export-refraction-eta).
TEST(ExportRender, EveryBuiltinsExportRendersOnTheDriverWithinTheImageTolerance) {
  skip_without_driver();
  if (IsSkipped()) return;
  const bool llvmpipe = on_llvmpipe();
  int compared = 0;
  for (const std::string& name : sdf::builtin_scene_names()) {
    const sdf::Scene scene = sdf::scaled_to_width(sdf::builtin_scene(name), 160);
    const std::vector<double> over = pixels_over(scene, {kValidateLevel, kLevel});
    RecordProperty(name + "_pixels_over", std::to_string(over[0]));
    RecordProperty(name + "_pixels_over_one_level", std::to_string(over[1]));
    EXPECT_LE(over[0], kValidateFraction) << name;
    if (llvmpipe && !on_the_drivers_transcendentals(name)) {
      EXPECT_LE(over[1], kLevelFraction) << name;
    }
    ++compared;
  }
  RecordProperty("compared", compared);
  EXPECT_EQ(compared, 32);
}

// What no built-in declares, exported and rendered all the same: each marcher, hit threshold, normal method,
// camera model, shadow kind and bias, fog, occlusion by samples, a mesh that fills the view, and mirrors. Held to
// validate's rule and to within one 8-bit level (kLevel).
TEST(ExportRender, EverySettingTheExportWritesRendersAsTheRenderer) {
  skip_without_driver();
  if (IsSkipped()) return;
  const bool llvmpipe = on_llvmpipe();
  struct Variant {
    const char* scene;
    std::vector<std::pair<const char*, const char*>> settings;
    void (*edit)(sdf::Scene&) = nullptr;
  };
  const Variant variants[] = {
      {"lee-flat", {{"marcher", "relaxed"}}},
      // L = 1.31: steps and unbounding spheres of f / L (sdf-export-relaxed-radius-dropped).
      {"lee-terrain", {{"marcher", "relaxed"}}},
      {"lee-flat", {{"marcher", "fixed"}, {"fixed_step", "0.2"}, {"max_steps", "400"}}},
      {"lee-flat", {{"marcher", "scaled"}, {"step_scale", "0.9"}}},
      // At a threshold this coarse, hits land 2 units short at grazing angles unless refined (sdf-export-secant-dropped).
      {"lee-flat", {{"refine", "secant"}, {"hit_eps", "0.1"}}},
      {"crum-torus", {{"eps_mode", "relative"}, {"hit_eps", "0.01"}}},
      {"crum-torus", {{"eps_mode", "pixel"}}},
      {"crum-torus", {{"camera.model", "orthographic"}, {"camera.ortho_height", "6"}}},
      {"crum-torus", {{"camera.model", "frustum"}}},
      {"lee-flat", {{"normal", "tetra"}, {"normal_eps_scaled", "true"}}},
      {"lee-flat", {{"normal", "forward"}}},
      {"lee-flat", {{"shadow", "soft"}}},
      // Hits nearer than 1000 hit thresholds ignored: no shadow left.
      {"lee-flat", {{"shadow_bias", "seed_ignore"}}, [](sdf::Scene& s) { s.lights[0].bias_factor = 1000; }},
      {"lee-flat", {{"effects.fog", "0.15"}}},
      {"lee-flat", {{"effects.ao", "samples"}, {"effects.ao_distance", "0.3"}, {"effects.ambient", "0.5"}}},
      {"flafla-occlusion", {{"camera.position", "1.5,0.8,1.6"}, {"camera.target", "1,0,0"}}},
      {"lee-textured", {{"camera.distance", "3"}}},  // the textures close up
      // A mirror sphere, two bounces deep, over a half-mirror ground.
      {"lee-flat", {{"effects.max_bounces", "2"}}, [](sdf::Scene& s) {
         for (sdf::Material& m : s.materials) m.reflectivity = 0.6;
       }},
  };
  for (const Variant& v : variants) {
    sdf::Scene scene = sdf::builtin_scene(v.scene);
    std::string label = v.scene;
    for (const auto& [key, value] : v.settings) {
      sdf::apply_setting(scene, key, value);
      label += std::string(" ") + key + "=" + value;
    }
    if (v.edit) v.edit(scene);
    const std::vector<double> over = pixels_over(sdf::scaled_to_width(scene, 160), {kValidateLevel, kLevel});
    RecordProperty(label, std::to_string(over[1]));
    EXPECT_LE(over[0], kValidateFraction) << label;
    if (llvmpipe) {
      EXPECT_LE(over[1], kLevelFraction) << label;
    }
  }
}

// Shadertoy compiles a shader as GLSL ES 3.00 (WebGL 2) around its own main: every export passes Khronos'
// reference compiler in that dialect (glslangValidator, from glslang-tools), not only the driver's GLSL 4.50.
// Broken variant: an int literal where ES needs a uint, which 4.50 converts and ES refuses (sdf-export-es-int-mask).
TEST(ExportRender, EveryExportCompilesAsShadertoysGlslEs300) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("marchcheck_es_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  int compiled = 0;
  for (const std::string& name : sdf::builtin_scene_names()) {
    const std::string shader = sdf::shadertoy_shader(sdf::builtin_scene(name));
    const std::filesystem::path file = dir / (name + ".frag"), log = dir / (name + ".log");
    std::ofstream(file) << "#version 300 es\nprecision highp float;\nprecision highp int;\nuniform vec3 iResolution;\n"
                           "uniform float iTime;\nuniform vec4 iMouse;\nuniform int iFrame;\nout vec4 shadertoy_out;\n"
                        << shader << "\nvoid main() { mainImage(shadertoy_out, gl_FragCoord.xy); }\n";
    const int status = std::system(("glslangValidator " + file.string() + " > " + log.string() + " 2>&1").c_str());
    std::ifstream in(log);
    EXPECT_EQ(status, 0) << name << ":\n" << std::string(std::istreambuf_iterator<char>(in), {});
    ++compiled;
  }
  std::filesystem::remove_all(dir);
  EXPECT_EQ(compiled, 32);
}

// The export's soil texture, run by marchcheck's GLSL evaluator (no driver needed), against the renderer's own
// lookup through OpenImageIO at points all over the picture and past its edges. 1e-4: the texels are computed in
// float where the picture's were in double (about 1e-6 apart); half a texel off moves the value by about 1e-3.
// Broken variant: the lookup from texel corners (sdf-export-texel-centres).
TEST(ExportRender, TheSoilTextureIsLookedUpAsOpenImageIODoes) {
  const std::string shader = sdf::shadertoy_shader(sdf::builtin_scene("lee-textured")) +
                             "float soilRed(vec3 p) { return mc_soil(p.x, p.y).r; }\n";
  sdf::GlslSpec spec;
  spec.function = "soilRed";
  spec.measured = false;
  const sdf::GlslField soil(spec, shader, "lee-textured.glsl");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 2.5);
  double worst = 0;
  for (int i = 0; i < 300; ++i) {
    const float s = static_cast<float>(u(rng)), t = static_cast<float>(u(rng));
    const double want = march::sample_texture(march::soil_texture_path(), s, t).x;
    worst = std::max(worst, std::abs(soil.distance(glm::vec3(s, t, 0)) - want));
  }
  RecordProperty("largest_difference", std::to_string(worst));
  EXPECT_LE(worst, 1e-4);
}

}  // namespace
}  // namespace marchcheck
