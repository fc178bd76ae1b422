// What marchcheck does through glslang and SPIRV-Tools, in a module of their own, libmarchcheck_glslang.so, loaded
// by the first GLSL input: linked into the sdf library, their relocations and 160 static constructors cost every
// command ~3 ms of start-up.
#pragma once

#include "marchcheck/sdf/glsl_field.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace marchcheck::sdf::glsl {

// Each as the function it serves says: glsl::compile_field, complete_glsl, glsl_declares_uniform, run_first_in.
struct GlslangModule {
  std::vector<std::uint32_t> (*compile_field)(const std::string& source, const std::string& file,
                                              const std::string& function);
  std::string (*complete)(const std::string& source, const std::string& file, const GlslEntry& entry);
  bool (*declares_uniform)(const std::string& source, const std::string& file, const std::string& name);
  std::string (*run_first_in)(const std::string& source, const std::string& file, const std::string& function,
                              const std::string& statement);
};

}  // namespace marchcheck::sdf::glsl
