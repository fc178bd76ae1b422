// EGL surfaceless + OpenGL 4.5 core: a fragment shader drawn into RGBA32F targets, in a child process bounded
// in time.
#include "marchcheck/gpu/driver.hpp"

// EGL and GL through libepoxy, which loads libEGL and libOpenGL on the first call (in the driver's child process):
// linked, with libGLdispatch, every command loaded them (1 to 1.5 ms of an empty program's start-up).
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <sstream>
#include <thread>

namespace marchcheck::gpu {

namespace {

// What the child hands back, in memory shared with the parent.
struct Shared {
  enum Status : int { ok, unavailable, refused } status = refused;
  double seconds = 0;
  char renderer[256] = {};
  char message[16384] = {};
};

void copy_text(char* to, std::size_t size, const std::string& text) {
  const std::size_t n = std::min(size - 1, text.size());
  std::memcpy(to, text.data(), n);
  to[n] = 0;
}

// A current OpenGL 4.5 core context on EGL's surfaceless platform (no window, no display server).
class Context {
 public:
  Context() {
    if (!epoxy_has_egl()) throw DriverUnavailable("libEGL.so.1 cannot be loaded (Debian's libegl1, libegl-mesa0)");
    const auto get_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_display) throw DriverUnavailable("no EGL driver (eglGetPlatformDisplayEXT is missing)");
    display_ = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display_ == EGL_NO_DISPLAY || !eglInitialize(display_, nullptr, nullptr))
      throw DriverUnavailable("EGL's surfaceless platform cannot be opened (Mesa's libegl-mesa0 and libgl1-mesa-dri)");
    if (!eglBindAPI(EGL_OPENGL_API)) throw DriverUnavailable("the EGL driver has no desktop OpenGL");
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context_ == EGL_NO_CONTEXT) throw DriverUnavailable("the EGL driver gives no OpenGL 4.5 core context");
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      throw DriverUnavailable("the OpenGL 4.5 context cannot be made current without a surface");
  }
  ~Context() {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

std::string program_log(GLuint object, bool shader) {
  GLint length = 0;
  (shader ? glGetShaderiv : glGetProgramiv)(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  (shader ? glGetShaderInfoLog : glGetProgramInfoLog)(object, length, nullptr, log.data());
  log.resize(std::strlen(log.c_str()));
  return log;
}

GLuint compiled(GLenum stage, const std::string& text, const std::string& file) {
  const GLuint shader = glCreateShader(stage);
  const char* source = text.c_str();
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) throw DriverError(file + ": the driver's compiler refuses the shader: " + program_log(shader, true));
  return shader;
}

// A triangle over the whole target, from gl_VertexID alone.
constexpr const char* kCoverVertex =
    "#version 450\nvoid main() { gl_Position = vec4(float(gl_VertexID & 1) * 4.0 - 1.0, "
    "float(gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); }\n";

GLuint linked_program(const DriverJob& job) {
  const GLuint program = glCreateProgram();
  glAttachShader(program, compiled(GL_VERTEX_SHADER, kCoverVertex, "(marchcheck's vertex shader)"));
  glAttachShader(program, compiled(GL_FRAGMENT_SHADER, job.shader, job.file));
  glLinkProgram(program);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) throw DriverError(job.file + ": the driver does not link the shader: " + program_log(program, false));
  return program;
}

// Each active uniform the job gives a value, converted to the uniform's type.
void set_uniforms(GLuint program, const DriverJob& job) {
  GLint count = 0;
  glGetProgramiv(program, GL_ACTIVE_UNIFORMS, &count);
  for (GLuint u = 0; u < static_cast<GLuint>(count); ++u) {
    char name[256];
    GLint size = 0;
    GLenum type = 0;
    glGetActiveUniform(program, u, sizeof name, nullptr, &size, &type, name);
    std::string key = name;
    if (key.ends_with("[0]")) key.resize(key.size() - 3);
    const auto given = job.uniforms.find(key);
    if (given == job.uniforms.end()) continue;
    const GLint at = glGetUniformLocation(program, name);
    std::vector<float> f(given->second.begin(), given->second.end());
    std::vector<GLint> i(given->second.begin(), given->second.end());
    const auto n = [&](std::size_t per) { return static_cast<GLsizei>(f.size() / per); };
    switch (type) {
      case GL_FLOAT: glProgramUniform1fv(program, at, n(1), f.data()); break;
      case GL_FLOAT_VEC2: glProgramUniform2fv(program, at, n(2), f.data()); break;
      case GL_FLOAT_VEC3: glProgramUniform3fv(program, at, n(3), f.data()); break;
      case GL_FLOAT_VEC4: glProgramUniform4fv(program, at, n(4), f.data()); break;
      case GL_INT: case GL_BOOL: glProgramUniform1iv(program, at, n(1), i.data()); break;
      case GL_INT_VEC2: glProgramUniform2iv(program, at, n(2), i.data()); break;
      case GL_INT_VEC3: glProgramUniform3iv(program, at, n(3), i.data()); break;
      case GL_INT_VEC4: glProgramUniform4iv(program, at, n(4), i.data()); break;
      default: throw DriverError(job.file + ": uniform " + key + " has a type marchcheck does not set");
    }
  }
}

void run_in_child(const DriverJob& job, Shared& shared, float* output) {
  const auto start = std::chrono::steady_clock::now();
  Context context;
  copy_text(shared.renderer, sizeof shared.renderer, reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  if (job.outputs < 1 || job.outputs > 8) throw DriverError(job.file + ": 1 to 8 outputs per invocation");
  const GLuint program = linked_program(job);
  glUseProgram(program);
  set_uniforms(program, job);
  const unsigned width = std::max(1u, std::min(job.width, job.invocations));
  const unsigned height = std::max(1u, (job.invocations + width - 1) / width);
  glUniform1ui(glGetUniformLocation(program, "marchcheck_width"), width);
  GLuint input = 0;
  glCreateBuffers(1, &input);
  glNamedBufferData(input, static_cast<GLsizeiptr>(std::max<std::size_t>(job.input.size(), 4) * sizeof(float)),
                    job.input.empty() ? nullptr : job.input.data(), GL_STATIC_DRAW);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, input);
  GLuint framebuffer = 0, vertices = 0;
  glCreateFramebuffers(1, &framebuffer);
  std::vector<GLuint> targets(job.outputs);
  std::vector<GLenum> attachments(job.outputs);
  glCreateTextures(GL_TEXTURE_2D, static_cast<GLsizei>(job.outputs), targets.data());
  for (unsigned a = 0; a < job.outputs; ++a) {
    glTextureStorage2D(targets[a], 1, GL_RGBA32F, static_cast<GLsizei>(width), static_cast<GLsizei>(height));
    attachments[a] = GL_COLOR_ATTACHMENT0 + a;
    glNamedFramebufferTexture(framebuffer, attachments[a], targets[a], 0);
  }
  glNamedFramebufferDrawBuffers(framebuffer, static_cast<GLsizei>(job.outputs), attachments.data());
  if (glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw DriverUnavailable("the driver has no RGBA32F render targets");
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, static_cast<GLsizei>(width), static_cast<GLsizei>(height));
  glCreateVertexArrays(1, &vertices);
  glBindVertexArray(vertices);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  std::vector<float> pixels(std::size_t{width} * height * 4);
  for (unsigned a = 0; a < job.outputs; ++a) {
    glGetTextureImage(targets[a], 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(pixels.size() * sizeof(float)),
                      pixels.data());
    for (unsigned i = 0; i < job.invocations; ++i)
      std::copy_n(pixels.data() + std::size_t{i} * 4, 4, output + (std::size_t{i} * job.outputs + a) * 4);
  }
  if (const GLenum e = glGetError(); e != GL_NO_ERROR)
    throw DriverError(job.file + ": the driver reports GL error " + std::to_string(e) + " running the shader");
  shared.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  shared.status = Shared::ok;
}

// The child's exit, as the parent waits for it: false when the time bound passed first.
bool waited(pid_t child, double seconds, int& status) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(child, &status, WNOHANG) == child) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return false;
}

}  // namespace

DriverResult run_on_driver(const DriverJob& job) {
  const std::size_t floats = std::size_t{job.invocations} * job.outputs * 4;
  const std::size_t bytes = sizeof(Shared) + floats * sizeof(float);
  void* memory = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (memory == MAP_FAILED) throw DriverError(job.file + ": no memory for the driver's results");
  Shared& shared = *new (memory) Shared;
  float* output = reinterpret_cast<float*>(static_cast<char*>(memory) + sizeof(Shared));
  struct Unmap {
    void* memory;
    std::size_t bytes;
    ~Unmap() { munmap(memory, bytes); }
  } unmap{memory, bytes};
  const pid_t child = fork();
  if (child < 0) throw DriverError(job.file + ": cannot start the driver's process");
  if (child == 0) {
    try {
      run_in_child(job, shared, output);
    } catch (const DriverUnavailable& e) {
      shared.status = Shared::unavailable;
      copy_text(shared.message, sizeof shared.message, e.what());
    } catch (const std::exception& e) {
      shared.status = Shared::refused;
      copy_text(shared.message, sizeof shared.message, e.what());
    }
    _exit(0);  // no exit handlers: the parent's, and the driver's, are not the child's to run
  }
  int status = 0;
  if (!waited(child, job.seconds_limit, status)) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
    std::ostringstream limit;
    limit << job.seconds_limit;
    throw DriverError(job.file + ": the shader did not finish within " + limit.str() +
                      " s on the driver (the bound on work) and was stopped: a loop that does not end?");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw DriverError(job.file + ": the driver's process ended abnormally (signal " +
                      std::to_string(WIFSIGNALED(status) ? WTERMSIG(status) : 0) + ") running the shader");
  if (shared.status == Shared::unavailable) throw DriverUnavailable(shared.message);
  if (shared.status != Shared::ok) throw DriverError(shared.message);
  return {std::vector<float>(output, output + floats), shared.renderer, shared.seconds};
}

std::string driver_renderer() {
  DriverJob probe;
  probe.shader = "#version 450\nlayout(location = 0) out vec4 o;\nvoid main() { o = vec4(1.0); }\n";
  probe.file = "(probe)";
  probe.invocations = 1;
  return run_on_driver(probe).renderer;
}

}  // namespace marchcheck::gpu
