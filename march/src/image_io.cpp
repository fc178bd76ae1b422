#include "marchcheck/march/render.hpp"

#include "image_module.hpp"
#include "marchcheck/files/atomic_file.hpp"

#include <png.h>
#include <tbb/parallel_for.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
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

// The byte to_8bit writes for a value: NaN black, as llvmpipe writes it (a GPU's driver may write anything); then
// clamped to [0, 1], through the sRGB curve or as it is, and rounded as lround(v * 255) without its library call:
// for x = v * 255 in [0, 255], x + 0.5 is exact in double, so its floor rounds halves up as lround does (in float,
// 0.49999997f + 0.5f would round to 1).
unsigned char eight_bit(float value, bool srgb) {
  const float raw = std::isnan(value) ? 0.0f : value;
  const float v = srgb ? to_srgb(raw) : std::clamp(raw, 0.0f, 1.0f);
  return static_cast<unsigned char>(std::floor(static_cast<double>(v * 255.0f) + 0.5));
}

// eight_bit(c, true) without a powf a sample (lee-flat's 1280x720 took 21 ms of one thread in powf): over the
// curve's power part, the floats between 0.0031308 and 1 in blocks of 2^13 consecutive bit patterns, each block's
// first byte and the first pattern of the next byte within it. Over a block the curve rises by at most 0.06 of a
// byte, so no block holds two steps. Built once with eight_bit itself, which assumes the bytes never fall as c
// rises (tested for every float in the range); every other value goes to eight_bit.
class SrgbBytes {
 public:
  SrgbBytes() {
    for (std::uint32_t k = 0; k < kBlocks; ++k) {
      const std::uint32_t first = kLow + (k << kShift), last = std::min(first + (1u << kShift), kHigh) - 1;
      base_[k] = eight_bit(std::bit_cast<float>(first), true);
      step_[k] = UINT32_MAX;  // none in the block
      if (eight_bit(std::bit_cast<float>(last), true) == base_[k]) continue;
      std::uint32_t lo = first, hi = last;  // eight_bit(lo) is the base, eight_bit(hi) is not
      while (hi - lo > 1) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        (eight_bit(std::bit_cast<float>(mid), true) == base_[k] ? lo : hi) = mid;
      }
      step_[k] = hi;
    }
  }
  unsigned char operator()(float value) const {
    const auto bits = std::bit_cast<std::uint32_t>(value);  // negatives and NaN lie above kHigh
    if (bits < kLow || bits >= kHigh) return eight_bit(value, true);
    const std::uint32_t k = (bits - kLow) >> kShift;
    return static_cast<unsigned char>(base_[k] + (bits >= step_[k]));
  }

 private:
  static constexpr int kShift = 13;
  static constexpr std::uint32_t kLow = std::bit_cast<std::uint32_t>(0.0031308f) + 1;  // the first powf
  static constexpr std::uint32_t kHigh = std::bit_cast<std::uint32_t>(1.0f);
  static constexpr std::uint32_t kBlocks = ((kHigh - kLow) >> kShift) + 1;
  std::array<unsigned char, kBlocks> base_;
  std::array<std::uint32_t, kBlocks> step_;
};

std::string base_of(const std::string& path) {
  const std::filesystem::path p(path);
  return (p.parent_path() / p.stem()).string();
}

}  // namespace

Bytes to_8bit(const Image& image, bool srgb) {
  Bytes bytes(image.pixels.size());
  // On every core, in blocks of 64 Ki samples: lee-flat's 1280x720 took one thread 5 ms raw. Through plain
  // pointers: a store through unsigned char may alias the vectors' own pointers, which the loop would then reload
  // at every sample.
  const float* values = image.pixels.data();
  unsigned char* out = bytes.data();
  const auto convert = [&](auto byte_of) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, bytes.size(), size_t(1) << 16), [=](const auto& block) {
      for (size_t i = block.begin(); i < block.end(); ++i) out[i] = byte_of(values[i]);
    });
  };
  if (srgb) {
    static const SrgbBytes curve;  // built by the first sRGB image, not by every process that writes one
    convert([](float value) { return curve(value); });
  } else {
    convert([](float value) { return eight_bit(value, false); });
  }
  return bytes;
}

namespace {

// A PNG's image data: the zlib stream of its rows, each behind the Sub filter (each byte less the one a pixel before
// it), deflated at level 3 in pieces of whole rows on every core as pigz does. Each piece is a raw deflate stream
// that ends on a byte boundary (Z_SYNC_FLUSH; the last one Z_FINISH), and the pieces follow one another between
// zlib's header and the Adler-32 of all the filtered rows. A piece starts without its predecessor's window, yet the
// files came out smaller than libpng's one stream (which uses zlib's Z_FILTERED strategy; these the default one):
// lee-flat 1280x720 150.1 -> 148.7 KB, crum-torus 48.2 -> 45.9 KB; lee-flat's whole command about 7 ms faster on 2
// cores (20 runs each).
std::vector<unsigned char> deflated_rows(const Bytes& bytes, size_t row, int rows, int pixel,
                                         const std::string& path) {
  constexpr size_t kPiece = 128 << 10;  // filtered bytes a piece, about: small images are one piece
  const int rows_per_piece = static_cast<int>(std::max<size_t>(1, kPiece / (row + 1)));
  const int pieces = (rows + rows_per_piece - 1) / rows_per_piece;
  struct Piece {
    std::vector<unsigned char> deflated;
    uLong adler = 0;
    size_t length = 0;
    bool ok = false;
  };
  std::vector<Piece> parts(static_cast<size_t>(pieces));
  tbb::parallel_for(0, pieces, [&](int k) {
    const int y0 = k * rows_per_piece, y1 = std::min(rows, y0 + rows_per_piece);
    std::vector<unsigned char> filtered((row + 1) * static_cast<size_t>(y1 - y0));
    for (int y = y0; y < y1; ++y) {
      const unsigned char* in = bytes.data() + static_cast<size_t>(y) * row;
      unsigned char* out = filtered.data() + static_cast<size_t>(y - y0) * (row + 1);
      out[0] = 1;  // PNG's filter type Sub
      for (size_t i = 0; i < row; ++i)
        out[1 + i] = static_cast<unsigned char>(in[i] - (i >= static_cast<size_t>(pixel) ? in[i - pixel] : 0));
    }
    Piece& part = parts[static_cast<size_t>(k)];
    part.adler = adler32(1, filtered.data(), static_cast<uInt>(filtered.size()));
    part.length = filtered.size();
    z_stream z{};
    if (deflateInit2(&z, 3, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) return;  // -15: raw, no header
    const bool last = k + 1 == pieces;
    part.deflated.resize(deflateBound(&z, filtered.size()) + 16);  // + a sync flush's empty block
    z.next_in = filtered.data();
    z.avail_in = static_cast<uInt>(filtered.size());
    z.next_out = part.deflated.data();
    z.avail_out = static_cast<uInt>(part.deflated.size());
    const int status = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
    // Whole: all input taken, and room left over, so that nothing of the flush is still held back.
    part.ok = (last ? status == Z_STREAM_END : status == Z_OK) && z.avail_in == 0 && z.avail_out > 0;
    part.deflated.resize(z.total_out);
    deflateEnd(&z);
  });
  std::vector<unsigned char> stream = {0x78, 0x5E};  // zlib: deflate, 32 KiB window, level 2 to 5; header check
  uLong adler = 1;
  for (const Piece& part : parts) {
    if (!part.ok) throw std::runtime_error(path + ": zlib could not compress the image");
    stream.insert(stream.end(), part.deflated.begin(), part.deflated.end());
    adler = adler32_combine(adler, part.adler, static_cast<z_off_t>(part.length));
  }
  for (int shift = 24; shift >= 0; shift -= 8) stream.push_back(static_cast<unsigned char>(adler >> shift));
  return stream;
}

// 8-bit PNG in memory through libpng: grey, grey and alpha, RGB or RGBA by the channel count; the transfer in a
// tEXt chunk (marchcheck:transfer) and, for sRGB, the sRGB chunk. Raw values get no gAMA 1.0, which would have a
// browser brighten them: they are what a shader's framebuffer shows as they are.
std::vector<unsigned char> encode_png(const Image& image, const std::string& path, const Bytes& bytes,
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
  if (srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  char key[] = "marchcheck:transfer", srgb_text[] = "srgb", linear_text[] = "linear";
  png_text text{};
  text.compression = PNG_TEXT_COMPRESSION_NONE;
  text.key = key;
  text.text = srgb ? srgb_text : linear_text;
  png_set_text(png, info, &text, 1);
  png_write_info(png, info);
  // The rows as one IDAT chunk that deflated_rows compresses (libpng's own writer is one thread), then the end.
  // zlib level 3, not 6: lee-flat at 1280x720 encodes about 18 ms faster (a sixth of the whole command) for a file
  // of 160 KB instead of 110 KB (level 1: 3 ms more saved, 200 KB). One row filter, Sub, rather than libpng's
  // choice among all five per row: lee-flat 27 -> 14 ms (150 KB), crum-torus 19 -> 6 ms (45 -> 48 KB), fogerty 15
  // -> 5 ms (18.5 -> 18.9 KB). No filter would be faster still but lets smooth renders grow (crum-torus 65 KB).
  const size_t row = static_cast<size_t>(image.width) * static_cast<size_t>(image.channels);
  const std::vector<unsigned char> data = deflated_rows(bytes, row, image.height, image.channels, path);
  png_write_chunk(png, reinterpret_cast<png_const_bytep>("IDAT"), data.data(), data.size());
  png_write_chunk(png, reinterpret_cast<png_const_bytep>("IEND"), nullptr, 0);
  png_destroy_write_struct(&png, &info);
  return out;
}

}  // namespace

void write_image(const Image& image, const std::string& path, bool srgb) {
  const std::string format = format_of(path);
  const bool as_float = is_float_format(format);
  const Bytes bytes = as_float ? Bytes{} : to_8bit(image, srgb);
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
