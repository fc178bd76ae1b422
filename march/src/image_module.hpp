// What marchcheck does through OpenImageIO (images in any format it writes or reads, textures), in a module of its
// own, libmarchcheck_oiio.so, loaded on first use: Debian's OpenImageIO links ~260 libraries (OpenCV, GDAL,
// ffmpeg), 160 ms of dynamic loading that every command paid when march linked it. The PNGs renders write go
// through libpng directly (image_io.cpp). OpenImageIO 2.4 also forces its bundled fmt settings on any file that
// includes it: it is included in oiio_module.cpp alone.
#pragma once

#include "marchcheck/march/render.hpp"

#include <string>
#include <vector>

namespace marchcheck::march {

struct ImageModule {
  // The image encoded as path's extension says (EXR, TIFF, JPEG, ...): floats for a float format, else `bytes`
  // (to_8bit's); srgb labels an 8-bit image's colour space. Throws std::runtime_error saying why it cannot.
  std::vector<unsigned char> (*encode)(const Image& image, const std::string& path, bool as_float,
                                       const Bytes& bytes, bool srgb);
  // Bilinear lookup, wrapping periodically, without MIP maps, at (s, t) in [0, 1): rgb (a grey image gives grey).
  void (*sample)(const std::string& path, float s, float t, float* rgb);
  // Why OpenImageIO cannot read path as an image; "" when it can.
  std::string (*unreadable)(const std::string& path);
};

// The module, loaded from beside libmarchcheck_march on first call (thread-safe). Throws std::runtime_error naming
// the file when it cannot be loaded.
const ImageModule& image_module();

}  // namespace marchcheck::march

// The module's one entry point.
extern "C" const marchcheck::march::ImageModule* marchcheck_image_module();
