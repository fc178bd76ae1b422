#include "marchcheck/march/texture.hpp"

#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/noise.hpp"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <filesystem>
#include <cmath>
#include <mutex>
#include <unistd.h>

namespace marchcheck::march {

namespace {

Image make_soil(int size) {
  Image img(size, size, 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      // Tileable fBm: lattice periods divide the image, so fract() lookups show no seams.
      double v = 0, amp = 0.5;
      for (int octave = 0; octave < 5; ++octave) {
        const double cells = 8 << octave;
        const double u = x * cells / size, w = y * cells / size;
        const auto period = static_cast<long long>(cells);
        const long long ix = static_cast<long long>(u), iy = static_cast<long long>(w);
        const double fx = u - static_cast<double>(ix), fy = w - static_cast<double>(iy);
        const double sx = fx * fx * (3 - 2 * fx), sy = fy * fy * (3 - 2 * fy);
        auto lattice = [&](long long i, long long j) { return sdf::lattice_value(i % period, j % period); };
        const double a = lattice(ix, iy), b = lattice(ix + 1, iy), c = lattice(ix, iy + 1), d = lattice(ix + 1, iy + 1);
        v += amp * ((a + (b - a) * sx) * (1 - sy) + (c + (d - c) * sx) * sy);
        amp *= 0.5;
      }
      float* p = img.at(x, y);
      // Sand to dark soil.
      p[0] = static_cast<float>(0.35 + 0.45 * v);
      p[1] = static_cast<float>(0.25 + 0.35 * v);
      p[2] = static_cast<float>(0.15 + 0.22 * v);
    }
  return img;
}

OIIO::TextureSystem* texture_system() {
  static OIIO::TextureSystem* ts = [] {
    auto* system = OIIO::TextureSystem::create(true);
    system->attribute("automip", 1);
    system->attribute("gray_to_rgb", 1);
    return system;
  }();
  return ts;
}

}  // namespace

const std::string& soil_texture_path() {
  static std::once_flag once;
  static std::string path;
  std::call_once(once, [] {
    const auto dir = std::filesystem::temp_directory_path() / "marchcheck-textures";
    std::filesystem::create_directories(dir);
    path = (dir / "soil-v1.exr").string();
    if (!std::filesystem::exists(path)) write_image(make_soil(512), path);
  });
  return path;
}

const std::string& texture_path(const sdf::Material& material) {
  return material.texture_file.empty() ? soil_texture_path() : material.texture_file;
}

void check_texture_files(const sdf::Scene& scene) {
  for (const sdf::Material& m : scene.materials) {
    if (m.texture_file.empty()) continue;
    const auto in = OIIO::ImageInput::open(m.texture_file);
    if (!in)
      throw sdf::SceneError("material '" + m.name + "': texture_file '" + m.texture_file +
                            "': not an image OpenImageIO can read (" + OIIO::geterror() + ")");
  }
}

glm::dvec3 sample_texture(const std::string& path, double s, double t) {
  OIIO::TextureOpt opt;
  opt.swrap = opt.twrap = OIIO::TextureOpt::WrapPeriodic;
  opt.interpmode = OIIO::TextureOpt::InterpBilinear;
  opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
  float rgb[3] = {0, 0, 0};
  // Wrapped in double first: OpenImageIO takes float coordinates, whose spacing at s = 2e5 (a point 1e6 from the
  // origin) is already a texel of a 1024 px image.
  const float s01 = static_cast<float>(s - std::floor(s)), t01 = static_cast<float>(t - std::floor(t));
  texture_system()->texture(OIIO::ustring(path), opt, s01, t01, 0, 0, 0, 0, 3, rgb);
  return {rgb[0], rgb[1], rgb[2]};
}

}  // namespace marchcheck::march
