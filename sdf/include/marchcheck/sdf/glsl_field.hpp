// A distance field written in GLSL, as people write it (Shadertoy, WebGL, Unity): its `map` function (any name)
// compiled by Khronos' glslang and evaluated on the CPU by an evaluator of the SPIR-V, in the tape's scalars:
// float (as a GPU computes it: IEEE, no contraction), double (the reference) and Dual (gradients).
#pragma once

#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/scalar.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace marchcheck::sdf {

// A GLSL source that does not compile, lacks the function, or uses what the evaluator does not run: the message
// names the file, and the line where there is one.
struct GlslError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What a glsl node says of its field.
struct GlslSpec {
  std::string source;            // the file, as the scene names it (resolved beside the scene file)
  std::string code;              // or the source text itself, inline in the scene
  std::string function = "map";  // float, vec2, vec3 or vec4 NAME(vec3 p): the distance is its .x
  std::map<std::string, std::vector<double>> uniforms;  // values of the shader's uniforms (others are 0)
  // What the field declares: exact, bound, lipschitz (with lipschitz, its constant) or unknown (measured).
  Kind kind = Kind::lipschitz;
  bool measured = true;  // the kind was not declared: the Lipschitz constant is measured at compile time
  double lipschitz = 1;
  // GLSL's mediump as mobile GPUs run it: the float evaluations computed in IEEE binary16 (half.hpp) instead;
  // double and dual numbers stay as they are. A node's "precision": "half", or --set precision=half.
  bool half = false;
  // The scene's materials (indices) that a vec2, vec3 or vec4 result's .y selects: .y rounded, 0 the first; any
  // other .y, or a float result, keeps the node's own. A node's "materials": [names].
  std::vector<int> materials;
};

namespace glsl {
struct Program;
}

class GlslField {
 public:
  // Compiles text (the file's contents; file names it in messages). Throws GlslError.
  GlslField(GlslSpec spec, const std::string& text, const std::string& file);
  const GlslSpec& spec() const { return spec_; }
  // The same compiled field, its float evaluations in binary16 (half) or in float.
  GlslField with_half(bool half) const;
  // SPIR-V instructions the evaluator runs per point, at most (loops aside).
  std::size_t instructions() const;

  // The field at p. T: float (binary16 when spec().half), double, Dual<float>, Dual<double>, Half. A shader that
  // runs past kMaxSteps instructions (a loop that does not end) or discards gives NaN; one that does so at the
  // origin is refused when compiled.
  template <class T>
  T distance(glm::vec<3, T> p) const;

  static constexpr std::uint64_t kMaxSteps = 1'000'000;

  // The scene material the result's .y selects at p (GlslSpec::materials, evaluated in double), or -1.
  int material(glm::dvec3 p) const;

 private:
  bool finishes_at_origin() const;
  bool exhausted() const;  // the last double evaluation on this thread ran out of steps
  GlslSpec spec_;
  std::shared_ptr<const glsl::Program> program_;
};

// What marchcheck puts around a user's source to make one GLSL 4.50 shader of it.
struct GlslEntry {
  std::string before;   // declarations the source may use (marchcheck's counters), before its text
  std::string after;    // the entry point, calling into the source, after it
  bool compute = false;  // a compute shader (the GL driver's runs), else a fragment shader (the CPU's)
  std::string expects;  // what a message about `after` means, e.g. "no function map(vec3) returning float"
};

// The source as one shader: Shadertoy's inputs it does not declare itself declared, a pasted shader's own main
// renamed, its lines counted from 1 (`#line 1`), the entry around it; checked by glslang. Throws GlslError
// "file:line: message".
std::string complete_glsl(const std::string& source, const std::string& file, const GlslEntry& entry);

// The source with `statement` run first in the body of function(vec3), as glslang locates its definition (how
// the GL driver's run counts the field's calls). Throws GlslError naming the function when the source does not
// define it, or defines it through a macro.
std::string run_first_in(const std::string& source, const std::string& file, const std::string& function,
                         const std::string& statement);

// The scene around a GLSL file given alone: its field (kind unknown: measured), marched in steps of f / L with the
// step limit, far distance and hit threshold the shader names for its own marcher (MAX_STEPS, MAX_DIST,
// SURF_DIST or their common spellings; stated in the description, else marchcheck's defaults), a camera
// framing the region where it is negative (found by sampling, stated in the description), a directional light
// with hard shadows, and materials y0 to y7 that a result's .y = 0 to 7 picks (unless spec names its own).
// Throws GlslError or SceneError naming the file.
Scene glsl_scene(const std::string& path, const std::string& function = "map");
// The same scene for the file's text as given (a sweep's overridden #defines) and the spec's function, uniforms
// and kind (its source becomes the path).
Scene glsl_scene(const std::string& path, GlslSpec spec, const std::string& text);

// A constant of the source (a #define or const global, such as MAX_STEPS), as a number; nullopt when the source
// has none by that name.
std::optional<double> glsl_constant(const std::string& text, const std::string& file, const std::string& name);

// Whether the source declares a uniform of that name (glslang's view of its globals).
bool glsl_declares_uniform(const std::string& source, const std::string& file, const std::string& name);

}  // namespace marchcheck::sdf
