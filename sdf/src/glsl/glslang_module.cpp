// libmarchcheck_glslang.so: GLSL to SPIR-V by Khronos' glslang, then SPIRV-Tools passes that inline every function and turn variables into
// SSA values, none that fold constants: the evaluator runs every operation the shader wrote, in its precision.
#include "glslang_module.hpp"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <spirv-tools/optimizer.hpp>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>

namespace marchcheck::sdf::glsl {

namespace {

// Shadertoy's inputs, declared for a source that does not declare them itself.
struct Uniform {
  const char* name;
  const char* declaration;
};
constexpr Uniform kShadertoy[] = {{"iTime", "uniform float iTime;"},
                                  {"iTimeDelta", "uniform float iTimeDelta;"},
                                  {"iFrameRate", "uniform float iFrameRate;"},
                                  {"iFrame", "uniform int iFrame;"},
                                  {"iResolution", "uniform vec3 iResolution;"},
                                  {"iMouse", "uniform vec4 iMouse;"},
                                  {"iDate", "uniform vec4 iDate;"},
                                  {"iSampleRate", "uniform float iSampleRate;"},
                                  {"iChannelTime", "uniform float iChannelTime[4];"},
                                  {"iChannelResolution", "uniform vec3 iChannelResolution[4];"},
                                  {"iChannel0", "uniform sampler2D iChannel0;"},
                                  {"iChannel1", "uniform sampler2D iChannel1;"},
                                  {"iChannel2", "uniform sampler2D iChannel2;"},
                                  {"iChannel3", "uniform sampler2D iChannel3;"}};

// The shader around the user's source: the entry's declarations, then the source (`#line 1` makes glslang's
// messages count the user's lines; a pasted shader's own main, WebGL's, is renamed so that ours is the entry
// point), then the entry's code.
std::string wrapped(const std::string& source, const GlslEntry& entry, const std::vector<bool>& declare) {
  std::ostringstream out;
  out << "#version 450\n";
  for (size_t i = 0; i < std::size(kShadertoy); ++i)
    if (declare[i]) out << kShadertoy[i].declaration << "\n";
  out << entry.before << "#define main marchcheck_user_main\n#line 1\n";
  // A #version of the user's own (WebGL's "300 es") would come after ours: kept as a blank line.
  std::istringstream in(source);
  std::string line;
  while (std::getline(in, line)) out << (line.rfind("#version", 0) == 0 ? "" : line) << "\n";
  out << "#undef main\n" << entry.after;
  return out.str();
}

// glslang's "ERROR: 0:12: 'x' : undeclared identifier" as "file:12: 'x' : undeclared identifier"; a message
// about the lines marchcheck adds after the user's (user_lines of them) says what the entry expected.
std::string messages(const std::string& log, const std::string& file, int user_lines, const std::string& expects) {
  std::istringstream in(log);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.empty() || line.find("compilation terminated") != std::string::npos ||
        line.find("compilation errors") != std::string::npos)
      continue;
    for (const std::string prefix : {"ERROR: 0:", "WARNING: 0:"}) {
      if (line.rfind(prefix, 0) != 0) continue;
      const std::string rest = line.substr(prefix.size());
      const int number = std::atoi(rest.c_str());
      line = number > user_lines ? file + ": " + expects + " (" + rest.substr(rest.find(':') + 1) + ")"
                                 : file + ":" + rest;
    }
    out += (out.empty() ? "" : "\n") + line;
  }
  return out;
}

bool parse(glslang::TShader& shader, EShLanguage stage, const std::string& text) {
  const char* strings[] = {text.c_str()};
  shader.setStrings(strings, 1);
  shader.setEnvInput(glslang::EShSourceGlsl, stage, glslang::EShClientOpenGL, 450);
  shader.setEnvClient(glslang::EShClientOpenGL, glslang::EShTargetOpenGL_450);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
  shader.setAutoMapBindings(true);  // bare `uniform float iTime;` needs a location and a binding
  shader.setAutoMapLocations(true);
  return shader.parse(GetDefaultResources(), 450, false, EShMsgDefault);
}

std::vector<std::uint32_t> optimised(const std::vector<std::uint32_t>& words) {
  spvtools::Optimizer opt(SPV_ENV_UNIVERSAL_1_0);
  opt.RegisterPass(spvtools::CreateMergeReturnPass())
      .RegisterPass(spvtools::CreateInlineExhaustivePass())
      .RegisterPass(spvtools::CreateEliminateDeadFunctionsPass())
      .RegisterPass(spvtools::CreatePrivateToLocalPass())
      .RegisterPass(spvtools::CreateScalarReplacementPass())
      .RegisterPass(spvtools::CreateLocalAccessChainConvertPass())
      .RegisterPass(spvtools::CreateLocalSingleBlockLoadStoreElimPass())
      .RegisterPass(spvtools::CreateLocalSingleStoreElimPass())
      .RegisterPass(spvtools::CreateAggressiveDCEPass())
      .RegisterPass(spvtools::CreateSSARewritePass())
      .RegisterPass(spvtools::CreateAggressiveDCEPass())
      .RegisterPass(spvtools::CreateDeadBranchElimPass())
      .RegisterPass(spvtools::CreateBlockMergePass())
      .RegisterPass(spvtools::CreateAggressiveDCEPass());
  std::vector<std::uint32_t> out;
  if (!opt.Run(words.data(), words.size(), &out)) throw GlslError("internal: the SPIR-V optimiser failed");
  return out;
}

// The completed shader, parsed, and how many of its lines are the user's (for messages).
struct Parsed {
  std::unique_ptr<glslang::TShader> shader;
  std::string text;
  int user_lines;
};

Parsed parsed(const std::string& source, const std::string& file, const GlslEntry& entry) {
  static std::once_flag init;
  std::call_once(init, [] { glslang::InitializeProcess(); });
  const EShLanguage stage = entry.compute ? EShLangCompute : EShLangFragment;
  std::vector<bool> declare(std::size(kShadertoy), true);
  const int user_lines = static_cast<int>(std::count(source.begin(), source.end(), '\n')) + 1;
  for (int attempt = 0;; ++attempt) {
    Parsed p{std::make_unique<glslang::TShader>(stage), wrapped(source, entry, declare), user_lines};
    if (parse(*p.shader, stage, p.text)) return p;
    const std::string log = p.shader->getInfoLog();
    // The source declares a Shadertoy input itself: not ours too.
    bool retry = false;
    for (size_t i = 0; i < std::size(kShadertoy); ++i)
      if (declare[i] && log.find(std::string("'") + kShadertoy[i].name + "' : redefinition") != std::string::npos) {
        declare[i] = false;
        retry = true;
      }
    if (!retry || attempt > 4) throw GlslError(messages(log, file, user_lines, entry.expects));
  }
}

// Where a function's definition begins its body: glslang places the definition at its prototype's ')'.
struct DefinitionFinder : glslang::TIntermTraverser {
  std::string mangled;  // glslang's name for NAME(vec3): "NAME(vf3;"
  std::optional<glslang::TSourceLoc> at;
  bool visitAggregate(glslang::TVisit, glslang::TIntermAggregate* node) override {
    if (node->getOp() != glslang::EOpFunction) return true;  // the sequence of the shader's definitions
    if (node->getName().c_str() == mangled) at = node->getLoc();
    return false;  // a definition holds no other definition
  }
};

// Whether a uniform of a name is among the shader's globals (the linker objects glslang lists).
struct UniformFinder : glslang::TIntermTraverser {
  std::string name;
  bool found = false;
  void visitSymbol(glslang::TIntermSymbol* symbol) override {
    found = found || (symbol->getQualifier().storage == glslang::EvqUniform && symbol->getName().c_str() == name);
  }
};

std::vector<std::uint32_t> field_spirv(const std::string& source, const std::string& file,
                                       const std::string& function) {
  const GlslEntry entry{"",
                        "layout(location = 0) in vec3 marchcheck_p;\n"
                        "layout(location = 0) out vec4 marchcheck_result;\n"
                        // The distance in .x, the material in .y (-1: none).
                        "vec4 marchcheck_pack(float d) { return vec4(d, -1.0, 0.0, 0.0); }\n"
                        "vec4 marchcheck_pack(vec2 d) { return vec4(d, 0.0, 0.0); }\n"
                        "vec4 marchcheck_pack(vec3 d) { return vec4(d, 0.0); }\n"
                        "vec4 marchcheck_pack(vec4 d) { return d; }\n"
                        "void main() { marchcheck_result = marchcheck_pack(" + function + "(marchcheck_p)); }\n",
                        false, "no function " + function + "(vec3) returning float, vec2, vec3 or vec4"};
  Parsed p = parsed(source, file, entry);
  glslang::TProgram program;
  program.addShader(p.shader.get());
  if (!program.link(EShMsgDefault)) throw GlslError(messages(program.getInfoLog(), file, p.user_lines, entry.expects));
  std::vector<std::uint32_t> words;
  glslang::SpvOptions options;
  options.disableOptimizer = true;  // ours, without constant folding
  glslang::GlslangToSpv(*program.getIntermediate(EShLangFragment), words, &options);
  return optimised(words);
}

std::string complete(const std::string& source, const std::string& file, const GlslEntry& entry) {
  return parsed(source, file, entry).text;
}

bool declares_uniform(const std::string& source, const std::string& file, const std::string& name) {
  Parsed p = parsed(source, file, {"", "void main() {}\n", false, ""});
  UniformFinder finder;
  finder.name = name;
  p.shader->getIntermediate()->getTreeRoot()->traverse(&finder);
  return finder.found;
}

std::string first_statement_in(const std::string& source, const std::string& file, const std::string& function,
                               const std::string& statement) {
  Parsed p = parsed(source, file, {"", "void main() {}\n", false, ""});
  DefinitionFinder finder;
  finder.mangled = function + "(vf3;";
  p.shader->getIntermediate()->getTreeRoot()->traverse(&finder);
  if (!finder.at) throw GlslError(file + ": no function " + function + "(vec3) is defined");
  // The ')' at (line, column), both from 1; the body's '{' after it, past white space.
  const auto fail = [&] {
    return GlslError(file + ":" + std::to_string(finder.at->line) + ": " + function +
                     "'s definition is not written out in the text (a macro?): its calls cannot be counted");
  };
  size_t pos = 0;
  for (int line = 1; line < finder.at->line; ++line) {
    pos = source.find('\n', pos);
    if (pos == std::string::npos) throw fail();
    ++pos;
  }
  pos += static_cast<size_t>(finder.at->column - 1);
  if (pos >= source.size() || source[pos] != ')') throw fail();
  // Past white space and comments, to the '{'.
  for (++pos; pos < source.size();) {
    if (std::isspace(static_cast<unsigned char>(source[pos]))) {
      ++pos;
    } else if (source.compare(pos, 2, "//") == 0) {
      pos = source.find('\n', pos);
    } else if (source.compare(pos, 2, "/*") == 0) {
      pos = source.find("*/", pos + 2);
      if (pos != std::string::npos) pos += 2;
    } else {
      break;
    }
  }
  if (pos >= source.size() || source[pos] != '{') throw fail();
  return source.substr(0, pos + 1) + " " + statement + " " + source.substr(pos + 1);
}

constexpr GlslangModule kModule{field_spirv, complete, declares_uniform, first_statement_in};

}  // namespace
}  // namespace marchcheck::sdf::glsl

extern "C" const marchcheck::sdf::glsl::GlslangModule* marchcheck_glslang_module() {
  return &marchcheck::sdf::glsl::kModule;
}
