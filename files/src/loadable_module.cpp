#include "marchcheck/files/loadable_module.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>

namespace marchcheck::files {

void* module_entry(const void* anchor, const std::string& module_file, const char* entry) {
  Dl_info self{};
  if (dladdr(anchor, &self) == 0 || !self.dli_fname)
    throw std::runtime_error("cannot tell where the library loading " + module_file + " was loaded from");
  const std::string path = (std::filesystem::path(self.dli_fname).parent_path() / module_file).string();
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw std::runtime_error(path + ": cannot load this marchcheck module: " + dlerror());
  void* address = dlsym(handle, entry);
  if (!address) throw std::runtime_error(path + ": no " + entry + " in it");
  return address;
}

}  // namespace marchcheck::files
