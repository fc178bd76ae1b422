#include "image_module.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>

namespace marchcheck::march {

const ImageModule& image_module() {
  static const ImageModule* module = [] {
    // Beside this library, in the build tree as once installed.
    Dl_info self{};
    if (dladdr(reinterpret_cast<const void*>(&image_module), &self) == 0 || !self.dli_fname)
      throw std::runtime_error("cannot tell where libmarchcheck_march was loaded from");
    const std::string path = (std::filesystem::path(self.dli_fname).parent_path() / "libmarchcheck_oiio.so").string();
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) throw std::runtime_error(path + ": cannot load marchcheck's OpenImageIO module: " + dlerror());
    const auto entry = reinterpret_cast<const ImageModule* (*)()>(dlsym(handle, "marchcheck_image_module"));
    if (!entry) throw std::runtime_error(path + ": no marchcheck_image_module in it");
    return entry();
  }();
  return *module;
}

}  // namespace marchcheck::march
