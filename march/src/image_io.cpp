// OpenImageIO lives in this file alone: OIIO 2.4 forces its bundled fmt settings on any file that includes it.
#include "marchcheck/march/render.hpp"

#include "marchcheck/files/atomic_file.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace marchcheck::march {

namespace {

bool is_float_format(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".exr" || ext == ".tif" || ext == ".tiff" || ext == ".hdr";
}

float to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

std::string base_of(const std::string& path) {
  const std::filesystem::path p(path);
  return (p.parent_path() / p.stem()).string();
}

}  // namespace

std::vector<unsigned char> to_8bit(const Image& image, bool srgb) {
  std::vector<unsigned char> bytes(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    // NaN is written black, as llvmpipe writes it (a GPU's driver may write anything; lround's is unspecified).
    const float raw = std::isnan(image.pixels[i]) ? 0.0f : image.pixels[i];
    const float v = srgb ? to_srgb(raw) : std::clamp(raw, 0.0f, 1.0f);
    bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
  }
  return bytes;
}

void write_image(const Image& image, const std::string& path, bool srgb) {
  const bool as_float = is_float_format(path);
  // Encoded in memory and written by write_bytes_atomically: OIIO's PNG writer reports no failed write (a disk
  // that fills up), and would leave a truncated image in place.
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error(path + ": no image writer for this extension (" + OIIO::geterror() + ")");
  if (!out->supports("ioproxy")) throw std::runtime_error(path + ": this image format cannot be written to memory");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  OIIO::ImageSpec spec(image.width, image.height, image.channels,
                       as_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!as_float) {
    // Raw values are what a shader's framebuffer shows as they are: no gAMA 1.0 (oiio:ColorSpace "linear"), which
    // would have a browser brighten them.
    if (srgb) spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("marchcheck:transfer", srgb ? "srgb" : "linear");
  }
  bool ok = out->set_ioproxy(&memory) && out->open(path, spec);
  if (ok) {
    if (as_float) {
      ok = out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
    } else {
      ok = out->write_image(OIIO::TypeDesc::UINT8, to_8bit(image, srgb).data());
    }
    ok = out->close() && ok;
  }
  if (!ok) throw std::runtime_error(path + ": cannot write the image: " + out->geterror());
  files::write_bytes_atomically(path, {reinterpret_cast<const char*>(bytes.data()), bytes.size()});
}

Image heat_map(const Image& values, double max_value) {
  // Five stops from dark blue through magenta and orange to light yellow (perceptually ordered, like inferno).
  static constexpr float stops[5][3] = {
      {0.02f, 0.02f, 0.10f}, {0.35f, 0.05f, 0.50f}, {0.80f, 0.20f, 0.35f}, {0.98f, 0.60f, 0.10f}, {0.98f, 0.98f, 0.65f}};
  Image out(values.width, values.height, 3);
  for (int y = 0; y < values.height; ++y)
    for (int x = 0; x < values.width; ++x) {
      // +inf (a NaN pixel's error: validate's difference image) at the top; NaN, and anything over no range, at 0.
      const double ratio = max_value > 0 ? *values.at(x, y) / max_value : 0;
      const double u = std::isnan(ratio) ? 0 : std::clamp(ratio, 0.0, 1.0) * 4;
      const int i = std::min(static_cast<int>(u), 3);
      const float f = static_cast<float>(u - i);
      float* c = out.at(x, y);
      for (int k = 0; k < 3; ++k) c[k] = stops[i][k] + (stops[i + 1][k] - stops[i][k]) * f;
    }
  return out;
}

void write_render(const RenderResult& r, const std::string& path, const std::vector<Aov>& aovs, const Image* error) {
  if (!error && std::find(aovs.begin(), aovs.end(), Aov::error) != aovs.end())
    throw std::invalid_argument("the error AOV needs the difference from a reference render");
  write_image(r.color, path, r.transfer == sdf::OutputTransfer::srgb);
  const std::string base = base_of(path);
  for (Aov aov : aovs) {
    switch (aov) {
      case Aov::depth: write_image(r.depth, base + ".depth.exr"); break;
      case Aov::normal: {
        Image shown = r.normal;
        for (auto& v : shown.pixels) v = v * 0.5f + 0.5f;
        write_image(shown, base + ".normal.png", false);
        break;
      }
      case Aov::steps: {
        const float top = *std::max_element(r.steps.pixels.begin(), r.steps.pixels.end());
        write_image(heat_map(r.steps, top), base + ".steps.png", false);
        break;
      }
      case Aov::evals: {
        const float top = *std::max_element(r.evals.pixels.begin(), r.evals.pixels.end());
        write_image(heat_map(r.evals, top), base + ".evals.png", false);
        break;
      }
      case Aov::stages:
        for (int stage = 0; stage < r.stage_evals.channels; ++stage) {
          Image one(r.stage_evals.width, r.stage_evals.height, 1);
          float top = 0;
          for (size_t i = 0; i < one.pixels.size(); ++i) {
            one.pixels[i] = r.stage_evals.pixels[i * static_cast<size_t>(r.stage_evals.channels) + static_cast<size_t>(stage)];
            top = std::max(top, one.pixels[i]);
          }
          if (top > 0) write_image(heat_map(one, top), base + ".evals-" + r.stage_names[static_cast<size_t>(stage)] + ".png", false);
        }
        break;
      case Aov::error: write_image(heat_map(*error, kErrorHeatMapMax), base + ".error.png", false); break;
      case Aov::id: {
        Image shown(r.id.width, r.id.height, 3);
        for (int y = 0; y < r.id.height; ++y)
          for (int x = 0; x < r.id.width; ++x) {
            const int id = static_cast<int>(*r.id.at(x, y));
            float* c = shown.at(x, y);
            // Golden-ratio hues keep neighbouring ids apart; misses stay black.
            for (int k = 0; k < 3; ++k)
              c[k] = id < 0 ? 0.0f : 0.5f + 0.45f * std::cos(6.2831853f * (0.618034f * static_cast<float>(id) + static_cast<float>(k) / 3.0f));
          }
        write_image(shown, base + ".id.png", false);
        break;
      }
    }
  }
}

}  // namespace marchcheck::march
