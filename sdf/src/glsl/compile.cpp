// GLSL's compilation, through the glslang module loaded on first use (glslang_module.hpp says why).
#include "glslang_module.hpp"
#include "program.hpp"

#include "marchcheck/files/loadable_module.hpp"

namespace marchcheck::sdf {

namespace glsl {
namespace {

const GlslangModule& glslang_module() {
  static const GlslangModule& module = files::module_table<GlslangModule>(
      reinterpret_cast<const void*>(&glslang_module), "libmarchcheck_glslang.so", "marchcheck_glslang_module");
  return module;
}

}  // namespace

std::vector<std::uint32_t> compile_field(const std::string& source, const std::string& file,
                                         const std::string& function) {
  return glslang_module().compile_field(source, file, function);
}

}  // namespace glsl

std::string complete_glsl(const std::string& source, const std::string& file, const GlslEntry& entry) {
  return glsl::glslang_module().complete(source, file, entry);
}

bool glsl_declares_uniform(const std::string& source, const std::string& file, const std::string& name) {
  return glsl::glslang_module().declares_uniform(source, file, name);
}

std::string run_first_in(const std::string& source, const std::string& file, const std::string& function,
                         const std::string& statement) {
  return glsl::glslang_module().run_first_in(source, file, function, statement);
}

}  // namespace marchcheck::sdf
