#include "marchcheck/march/render.hpp"

#include "huge_pages.hpp"
#include "image_module.hpp"
#include "marchcheck/files/atomic_file.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace marchcheck::march {

namespace {

// The extension naming a file's format, in lower case (".PNG" is ".png").
std::string format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool is_float_format(const std::string& format) {
  return format == ".exr" || format == ".tif" || format == ".tiff" || format == ".hdr";
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
  std::vector<unsigned char> bytes;
  bytes.reserve(image.pixels.size());
  advise_huge_pages(bytes.data(), image.pixels.size());
  bytes.resize(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    // NaN is written black, as llvmpipe writes it (a GPU's driver may write anything).
    const float raw = std::isnan(image.pixels[i]) ? 0.0f : image.pixels[i];
    const float v = srgb ? to_srgb(raw) : std::clamp(raw, 0.0f, 1.0f);
    // lround(v * 255) without its library call: for x = v * 255 in [0, 255], x + 0.5 is exact in double, so its
    // floor rounds halves up as lround does (in float, 0.49999997f + 0.5f would round to 1).
    bytes[i] = static_cast<unsigned char>(std::floor(static_cast<double>(v * 255.0f) + 0.5));
  }
  return bytes;
}

namespace {

// 8-bit PNG in memory through libpng: grey, grey and alpha, RGB or RGBA by the channel count; the transfer in a
// tEXt chunk (marchcheck:transfer) and, for sRGB, the sRGB chunk. Raw values get no gAMA 1.0, which would have a
// browser brighten them: they are what a shader's framebuffer shows as they are.
std::vector<unsigned char> encode_png(const Image& image, const std::string& path, const std::vector<unsigned char>& bytes,
                                      bool srgb) {
  static constexpr int kColorType[5] = {-1, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                        PNG_COLOR_TYPE_RGBA};
  if (image.channels < 1 || image.channels > 4)
    throw std::runtime_error(path + ": a PNG holds 1 to 4 channels, not " + std::to_string(image.channels));
  std::vector<unsigned char> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error(path + ": libpng could not start");
  }
  if (setjmp(png_jmpbuf(png))) {  // libpng's errors arrive here
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error(path + ": libpng could not encode the image");
  }
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, png_size_t n) {
        auto* buffer = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(p));
        buffer->insert(buffer->end(), data, data + n);
      },
      nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               kColorType[image.channels], PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // zlib level 3, not 6: lee-flat at 1280x720 encodes about 18 ms faster (a sixth of the whole command) for a file
  // of 160 KB instead of 110 KB (level 1: 3 ms more saved, 200 KB). One row filter, Sub, rather than libpng's
  // choice among all five per row: lee-flat 27 -> 14 ms (150 KB), crum-torus 19 -> 6 ms (45 -> 48 KB), fogerty 15
  // -> 5 ms (18.5 -> 18.9 KB). No filter would be faster still but lets smooth renders grow (crum-torus 65 KB).
  png_set_compression_level(png, 3);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  if (srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  char key[] = "marchcheck:transfer", srgb_text[] = "srgb", linear_text[] = "linear";
  png_text text{};
  text.compression = PNG_TEXT_COMPRESSION_NONE;
  text.key = key;
  text.text = srgb ? srgb_text : linear_text;
  png_set_text(png, info, &text, 1);
  png_write_info(png, info);
  const size_t row = static_cast<size_t>(image.width) * static_cast<size_t>(image.channels);
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(bytes.data() + static_cast<size_t>(y) * row));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return out;
}

}  // namespace

void write_image(const Image& image, const std::string& path, bool srgb) {
  const std::string format = format_of(path);
  const bool as_float = is_float_format(format);
  const std::vector<unsigned char> bytes = as_float ? std::vector<unsigned char>{} : to_8bit(image, srgb);
  const std::vector<unsigned char> encoded =
      format == ".png" ? encode_png(image, path, bytes, srgb) : image_module().encode(image, path, as_float, bytes, srgb);
  files::write_bytes_atomically(path, {reinterpret_cast<const char*>(encoded.data()), encoded.size()});
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
