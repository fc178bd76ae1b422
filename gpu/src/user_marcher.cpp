// The shaders around a user's source for the driver: its marcher per pixel (a pixel a ray), or its field.
#include "marchcheck/gpu/user_marcher.hpp"

#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/half.hpp"

#include <array>
#include <memory>

namespace marchcheck::gpu {

namespace {

// The distance (or t) of any of GLSL's result forms.
constexpr const char* kFirstComponent =
    "float marchcheck_x(float d) { return d; }\n"
    "float marchcheck_x(vec2 d) { return d.x; }\n"
    "float marchcheck_x(vec3 d) { return d.x; }\n"
    "float marchcheck_x(vec4 d) { return d.x; }\n";

// The pixel's invocation index and the input it reads, and kFirstComponent.
const std::string kPixelInput =
    std::string("layout(std430, binding = 0) readonly buffer MarchcheckInput { vec4 marchcheck_input[]; };\n"
                "uniform uint marchcheck_width;\n"
                "uint marchcheck_index() { return uint(gl_FragCoord.y) * marchcheck_width + uint(gl_FragCoord.x); }\n") +
    kFirstComponent;

std::vector<float> flattened(const std::vector<glm::dvec3>& points) {
  std::vector<float> out;
  out.reserve(points.size() * 4);
  for (const glm::dvec3& p : points)
    for (double c : {p.x, p.y, p.z, 0.0}) out.push_back(static_cast<float>(c));
  return out;
}

// The marcher's call for ro and rd, its t as a float: "marchcheck_x(NAME(ro, rd))" or ".member" of a struct.
std::string march_call(const UserMarcher& marcher, const std::string& ro, const std::string& rd) {
  const auto dot = marcher.march.find('.');
  const std::string member = dot == std::string::npos ? "" : marcher.march.substr(dot);
  return "marchcheck_x(" + marcher.march.substr(0, dot) + "(" + ro + ", " + rd + ")" + member + ")";
}

// What a message about marchcheck's code around the marcher means.
std::string marcher_expected(const UserMarcher& marcher) {
  const auto dot = marcher.march.find('.');
  return "no marcher " + marcher.march.substr(0, dot) + "(vec3 ro, vec3 rd) returning float, vec2, vec3 or vec4" +
         (dot == std::string::npos ? "" : " or a struct with member " + marcher.march.substr(dot + 1)) +
         (marcher.normal.empty() ? "" : ", or no normal " + marcher.normal + "(vec3) returning vec3");
}

// The source with its field's calls counted in marchcheck_calls.
std::string counted_source(const std::string& text, const std::string& file, const UserMarcher& marcher) {
  return sdf::run_first_in(text, file, marcher.map, "marchcheck_calls++;");
}

}  // namespace

UserMarch march_on_driver(const std::string& text, const std::string& file, const UserMarcher& marcher,
                          const std::map<std::string, std::vector<double>>& uniforms,
                          const std::vector<std::pair<glm::dvec3, glm::dvec3>>& rays, double seconds_limit) {
  std::string after = kPixelInput;
  after += "layout(location = 0) out vec4 marchcheck_march;\n"
           "layout(location = 1) out vec4 marchcheck_normal;\n"
           "void main() {\n"
           "  uint i = marchcheck_index();\n"
           "  vec3 ro = marchcheck_input[2u * i].xyz, rd = marchcheck_input[2u * i + 1u].xyz;\n"
           "  marchcheck_calls = 0u;\n"
           "  float t = " + march_call(marcher, "ro", "rd") + ";\n"
           "  marchcheck_march = vec4(t, float(marchcheck_calls), 0.0, 0.0);\n";
  after += marcher.normal.empty() ? "  marchcheck_normal = vec4(0.0);\n"
                                  : "  marchcheck_normal = vec4(" + marcher.normal + "(ro + rd * t), 1.0);\n";
  after += "}\n";
  const std::string counted = counted_source(text, file, marcher);
  DriverJob job;
  job.shader = sdf::complete_glsl(counted, file, {"uint marchcheck_calls;\n", after, false, marcher_expected(marcher)});
  job.file = file;
  for (const auto& [origin, direction] : rays)
    for (double c : {origin.x, origin.y, origin.z, 0.0, direction.x, direction.y, direction.z, 0.0})
      job.input.push_back(static_cast<float>(c));
  job.outputs = 2;
  job.invocations = static_cast<unsigned>(rays.size());
  job.uniforms = uniforms;
  job.seconds_limit = seconds_limit;
  const DriverResult run = run_on_driver(job);
  UserMarch out{{}, run.renderer, run.seconds};
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const float* o = run.output.data() + i * 8;
    UserRay r{o[0], static_cast<int>(o[1]), std::nullopt};
    if (o[7] == 1.0f) r.normal = glm::dvec3(o[4], o[5], o[6]);
    out.rays.push_back(r);
  }
  return out;
}

template <class T>
std::vector<double> march_on_cpu(const std::string& text, const std::string& file, const UserMarcher& marcher,
                                 const std::map<std::string, std::vector<double>>& uniforms,
                                 const std::vector<std::pair<glm::dvec3, glm::dvec3>>& rays) {
  // The evaluator's input is one vec3: the direction; the origin is a uniform, one compiled field per origin (a
  // pinhole camera's rays share theirs). The counter is declared ahead of the source, whose lines still count
  // from 1.
  const std::string source = "uint marchcheck_calls;\n#line 1\n" + counted_source(text, file, marcher) +
                             "\nuniform vec3 marchcheck_ro;\n" + kFirstComponent +
                             "float marchcheck_march(vec3 rd) { marchcheck_calls = 0u; return " +
                             march_call(marcher, "marchcheck_ro", "rd") + "; }\n";
  std::map<std::array<double, 3>, std::shared_ptr<const sdf::GlslField>> by_origin;
  std::vector<double> out;
  for (const auto& [origin, direction] : rays) {
    auto& field = by_origin[{origin.x, origin.y, origin.z}];
    if (!field) {
      sdf::GlslSpec spec;
      spec.function = "marchcheck_march";
      spec.measured = false;
      spec.uniforms = uniforms;
      spec.uniforms["marchcheck_ro"] = {origin.x, origin.y, origin.z};
      field = std::make_shared<const sdf::GlslField>(spec, source, file);
    }
    out.push_back(static_cast<double>(field->distance(glm::vec<3, T>(direction))));
  }
  return out;
}

template std::vector<double> march_on_cpu<float>(const std::string&, const std::string&, const UserMarcher&,
                                                 const std::map<std::string, std::vector<double>>&,
                                                 const std::vector<std::pair<glm::dvec3, glm::dvec3>>&);
template std::vector<double> march_on_cpu<sdf::Half>(const std::string&, const std::string&, const UserMarcher&,
                                                     const std::map<std::string, std::vector<double>>&,
                                                     const std::vector<std::pair<glm::dvec3, glm::dvec3>>&);
template std::vector<double> march_on_cpu<double>(const std::string&, const std::string&, const UserMarcher&,
                                                  const std::map<std::string, std::vector<double>>&,
                                                  const std::vector<std::pair<glm::dvec3, glm::dvec3>>&);

std::vector<float> field_on_driver(const std::string& text, const std::string& file, const std::string& function,
                                   const std::map<std::string, std::vector<double>>& uniforms,
                                   const std::vector<glm::dvec3>& points, double seconds_limit) {
  const std::string after = kPixelInput +
                            "layout(location = 0) out vec4 marchcheck_result;\n"
                            "void main() { marchcheck_result = vec4(marchcheck_x(" + function +
                            "(marchcheck_input[marchcheck_index()].xyz))); }\n";
  DriverJob job;
  job.shader = sdf::complete_glsl(
      text, file, {"", after, false, "no function " + function + "(vec3) returning float, vec2, vec3 or vec4"});
  job.file = file;
  job.input = flattened(points);
  job.invocations = static_cast<unsigned>(points.size());
  job.uniforms = uniforms;
  job.seconds_limit = seconds_limit;
  const DriverResult run = run_on_driver(job);
  std::vector<float> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = run.output[i * 4];
  return out;
}

std::vector<float> render_shadertoy(const std::string& text, const std::string& file, int width, int height,
                                    double seconds_limit) {
  DriverJob job;
  job.shader = sdf::complete_glsl(text, file,
                                  {"",
                                   "layout(location = 0) out vec4 marchcheck_color;\n"
                                   "void main() { vec4 c = vec4(0.0); mainImage(c, gl_FragCoord.xy); marchcheck_color = c; }\n",
                                   false, "no mainImage(out vec4 fragColor, in vec2 fragCoord)"});
  job.file = file;
  job.invocations = static_cast<unsigned>(width * height);
  job.width = static_cast<unsigned>(width);
  job.uniforms["iResolution"] = {double(width), double(height), 1.0};
  job.seconds_limit = seconds_limit;
  return run_on_driver(job).output;
}

}  // namespace marchcheck::gpu
