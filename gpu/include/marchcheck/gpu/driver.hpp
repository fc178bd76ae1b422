// A real GL driver without a display: desktop OpenGL 4.5 core through EGL's surfaceless platform (Mesa's
// llvmpipe on a machine without a GPU, the GPU's own driver where there is one), running fragment shaders into
// float (RGBA32F) targets: a fragment shader, as Shadertoy's run, may use everything a pasted shader does
// (derivatives included). Each run happens in a child process: a shader that never ends is stopped by a time bound and
// a driver that crashes takes only the child with it.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace marchcheck::gpu {

// No GL driver could be opened (no EGL, no surfaceless platform, no OpenGL 4.5 context): what was missing.
struct DriverUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The driver refused the shader, or the run did not finish within its time bound.
struct DriverError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One draw of a fragment shader over `invocations` pixels of RGBA32F targets `width` wide: pixel (x, y) is
// invocation y * width + x. The shader reads `input` at SSBO binding 0 (std430) and writes `outputs` vec4s at
// locations 0, 1, ...; the uniform `marchcheck_width` is the targets' width.
struct DriverJob {
  std::string shader;  // GLSL 4.50 fragment shader text
  std::string file;    // named in the driver's messages
  std::vector<float> input;
  unsigned outputs = 1;  // vec4 outputs per invocation, at most 8
  unsigned invocations = 0;
  unsigned width = 1024;  // of the targets (fewer when there are fewer invocations)
  std::map<std::string, std::vector<double>> uniforms;  // the shader's own uniforms by name (others stay 0)
  double seconds_limit = 60;  // the bound on work: a run that takes longer is stopped
};

struct DriverResult {
  std::vector<float> output;  // per invocation, its outputs' 4 components each
  std::string renderer;       // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  double seconds = 0;         // the whole run: context, compile, draw and read back
};

// Runs the job on the driver. Throws DriverUnavailable, or DriverError with the driver's message naming the file.
DriverResult run_on_driver(const DriverJob& job);

// The renderer string of the driver that run_on_driver would use; throws DriverUnavailable.
std::string driver_renderer();

}  // namespace marchcheck::gpu
