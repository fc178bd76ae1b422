#include "image_module.hpp"

#include "marchcheck/files/loadable_module.hpp"

namespace marchcheck::march {

const ImageModule& image_module() {
  static const ImageModule& module = files::module_table<ImageModule>(
      reinterpret_cast<const void*>(&image_module), "libmarchcheck_oiio.so", "marchcheck_image_module");
  return module;
}

}  // namespace marchcheck::march
