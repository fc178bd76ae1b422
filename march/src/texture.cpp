#include "marchcheck/march/texture.hpp"

#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/noise.hpp"

#include "image_module.hpp"

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
    if (const std::string why = image_module().unreadable(m.texture_file); !why.empty())
      throw sdf::SceneError("material '" + m.name + "': texture_file '" + m.texture_file +
                            "': not an image OpenImageIO can read (" + why + ")");
  }
}

glm::dvec3 sample_texture(const std::string& path, double s, double t) {
  float rgb[3];
  // Wrapped in double first: OpenImageIO takes float coordinates, whose spacing at s = 2e5 (a point 1e6 from the
  // origin) is already a texel of a 1024 px image.
  const float s01 = static_cast<float>(s - std::floor(s)), t01 = static_cast<float>(t - std::floor(t));
  image_module().sample(path, s01, t01, rgb);
  return {rgb[0], rgb[1], rgb[2]};
}

}  // namespace marchcheck::march
