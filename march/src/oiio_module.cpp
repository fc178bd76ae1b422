// libmarchcheck_oiio.so: OpenImageIO behind image_module.hpp's table.
#include "image_module.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <stdexcept>

namespace marchcheck::march {
namespace {

std::vector<unsigned char> encode(const Image& image, const std::string& path, bool as_float,
                                  const Bytes& bytes, bool srgb) {
  // Encoded in memory and written by write_bytes_atomically: OIIO's writers report no failed write (a disk that
  // fills up), and would leave a truncated image in place.
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error(path + ": no image writer for this extension (" + OIIO::geterror() + ")");
  if (!out->supports("ioproxy")) throw std::runtime_error(path + ": this image format cannot be written to memory");
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  OIIO::ImageSpec spec(image.width, image.height, image.channels, as_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!as_float) {
    if (srgb) spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("marchcheck:transfer", srgb ? "srgb" : "linear");
  }
  bool ok = out->set_ioproxy(&memory) && out->open(path, spec);
  if (ok) {
    ok = as_float ? out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data())
                  : out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    ok = out->close() && ok;
  }
  if (!ok) throw std::runtime_error(path + ": cannot write the image: " + out->geterror());
  return encoded;
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

void sample(const std::string& path, float s, float t, float* rgb) {
  OIIO::TextureOpt opt;
  opt.swrap = opt.twrap = OIIO::TextureOpt::WrapPeriodic;
  opt.interpmode = OIIO::TextureOpt::InterpBilinear;
  opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
  rgb[0] = rgb[1] = rgb[2] = 0;
  texture_system()->texture(OIIO::ustring(path), opt, s, t, 0, 0, 0, 0, 3, rgb);
}

std::string unreadable(const std::string& path) {
  const auto in = OIIO::ImageInput::open(path);
  return in ? "" : OIIO::geterror();
}

constexpr ImageModule kModule{encode, sample, unreadable};

}  // namespace
}  // namespace marchcheck::march

extern "C" const marchcheck::march::ImageModule* marchcheck_image_module() { return &marchcheck::march::kModule; }
