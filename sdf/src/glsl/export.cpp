// A scene as a self-contained GLSL shader: its compiled tape written out instruction by instruction over GLSL
// kernels that mirror the C++ ones expression for expression (so that marchcheck's own GLSL evaluator gives the
// tape's float values bit for bit), and, for Shadertoy, a mainImage with the scene's camera, marcher, normals,
// lights and hard shadows.
#include "marchcheck/sdf/glsl_export.hpp"

#include "marchcheck/sdf/tape.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <map>
#include <numbers>
#include <sstream>

namespace marchcheck::sdf {

namespace {

// smath's helpers as GLSL, the same operations in the same order: GLSL's own min, max, clamp, mix and round
// are not specified to (NaN, signed zeros, mix's a (1 - t) + b t, round's ties).
constexpr const char* kHelpers = R"(float mc_min(float a, float b) { return b < a ? b : a; }
float mc_max(float a, float b) { return a < b ? b : a; }
float mc_clamp(float x, float lo, float hi) { return mc_min(mc_max(x, lo), hi); }
float mc_mix(float a, float b, float t) { return a + (b - a) * t; }
float mc_round(float x) { return floor(x + 0.5); }
float mc_sign(float x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }
float mc_dot(vec2 a, vec2 b) { float s = a.x * b.x; s += a.y * b.y; return s; }
float mc_dot(vec3 a, vec3 b) { float s = a.x * b.x; s += a.y * b.y; s += a.z * b.z; return s; }
float mc_length(vec2 a) { return sqrt(mc_dot(a, a)); }
float mc_length(vec3 a) { return sqrt(mc_dot(a, a)); }
vec2 mc_max(vec2 a, float b) { return vec2(mc_max(a.x, b), mc_max(a.y, b)); }
vec3 mc_max(vec3 a, float b) { return vec3(mc_max(a.x, b), mc_max(a.y, b), mc_max(a.z, b)); }
float mc_max_component(vec3 a) { return mc_max(mc_max(a.x, a.y), a.z); }
float mc_box_distance(vec3 q) { return mc_length(mc_max(q, 0.0)) + mc_min(mc_max_component(q), 0.0); }
float mc_smooth_min(float a, float b, float k) {
  float h = mc_max(k - abs(a - b), 0.0) / k;
  return mc_min(a, b) - h * h * k * 0.25;
}
)";

// Each kernel's GLSL: the C++ kernel's expressions, K[at + i] for its k(i). Empty: not exportable (why).
struct GlslKernel {
  const char* code;
  const char* why_not = "";
  bool extra = false;  // also takes one constant the C++ kernel derives in double (its index in K)
};

// clang-format off
const std::map<TapeOp, GlslKernel>& glsl_kernels() {
  static const std::map<TapeOp, GlslKernel> kernels = {
    {TapeOp::sphere, {"float k_sphere(int at, vec3 p) { return mc_length(p) - K[at]; }"}},
    {TapeOp::plane, {"float k_plane(int at, vec3 p) { return p.x * K[at] + p.y * K[at + 1] + p.z * K[at + 2] + K[at + 3]; }"}},
    {TapeOp::box, {"float k_box(int at, vec3 p) { return mc_box_distance(abs(p) - vec3(K[at], K[at + 1], K[at + 2])); }"}},
    {TapeOp::round_box, {"float k_round_box(int at, vec3 p) { float r = K[at + 3];\n"
                         "  return mc_box_distance(abs(p) - vec3(K[at], K[at + 1], K[at + 2]) + vec3(r)) - r; }"}},
    {TapeOp::box_frame, {"float k_box_frame(int at, vec3 p) { vec3 b = vec3(K[at], K[at + 1], K[at + 2]);\n"
                         "  float e = K[at + 3] * 0.5; vec3 q = abs(p) - b; vec3 w = abs(q + vec3(e)) - vec3(e);\n"
                         "  return mc_min(mc_min(mc_box_distance(vec3(q.x, w.y, w.z)), mc_box_distance(vec3(w.x, q.y, w.z))),\n"
                         "                mc_box_distance(vec3(w.x, w.y, q.z))); }"}},
    {TapeOp::torus, {"float k_torus(int at, vec3 p) { vec2 q = vec2(mc_length(vec2(p.x, p.z)) - K[at], p.y);\n"
                     "  return mc_length(q) - K[at + 1]; }"}},
    {TapeOp::capped_torus, {"float k_capped_torus(int at, vec3 p) { float sx = K[at], cy = K[at + 1], ra = K[at + 2], rb = K[at + 3];\n"
                            "  p.x = abs(p.x); float kk = cy * p.x > sx * p.y ? p.x * sx + p.y * cy : mc_length(vec2(p.x, p.y));\n"
                            "  return sqrt(mc_max(mc_dot(p, p) + ra * ra - 2.0 * ra * kk, 0.0)) - rb; }"}},
    {TapeOp::capsule, {"float k_capsule(int at, vec3 p) { vec3 pa = p - vec3(K[at], K[at + 1], K[at + 2]);\n"
                       "  vec3 ba = vec3(K[at + 3], K[at + 4], K[at + 5]); float h = mc_clamp(mc_dot(pa, ba) * K[at + 6], 0.0, 1.0);\n"
                       "  return mc_length(pa - ba * h) - K[at + 7]; }"}},
    {TapeOp::capped_cylinder, {"float k_capped_cylinder(int at, vec3 p) {\n"
                               "  vec2 d = abs(vec2(mc_length(vec2(p.x, p.z)), p.y)) - vec2(K[at + 1], K[at]);\n"
                               "  return mc_min(mc_max(d.x, d.y), 0.0) + mc_length(mc_max(d, 0.0)); }"}},
    {TapeOp::cone, {"float k_cone(int at, vec3 p) { vec2 q = vec2(K[at], K[at + 1]); vec2 w = vec2(mc_length(vec2(p.x, p.z)), p.y);\n"
                    "  vec2 ea = w - q * mc_clamp(mc_dot(w, q) / mc_dot(q, q), 0.0, 1.0);\n"
                    "  vec2 eb = w - q * vec2(mc_clamp(w.x / q.x, 0.0, 1.0), 1.0);\n"
                    "  float d = mc_min(mc_dot(ea, ea), mc_dot(eb, eb));\n"
                    "  float s = mc_max(-(w.x * q.y - w.y * q.x), -(w.y - q.y)); return sqrt(d) * mc_sign(s); }"}},
    {TapeOp::ellipsoid, {"float k_ellipsoid(int at, vec3 p) { vec3 r = vec3(K[at], K[at + 1], K[at + 2]);\n"
                         "  float k0 = mc_length(vec3(p.x / r.x, p.y / r.y, p.z / r.z)); float smallest = mc_min(r.x, mc_min(r.y, r.z));\n"
                         "  if (k0 < 1.0) return (k0 - 1.0) * smallest;\n"
                         "  float k1 = mc_length(vec3(p.x / (r.x * r.x), p.y / (r.y * r.y), p.z / (r.z * r.z)));\n"
                         "  return k0 * (k0 - 1.0) / k1; }"}},
    {TapeOp::octahedron, {"float k_octahedron(int at, vec3 p) { float s = K[at]; p = abs(p); float m = p.x + p.y + p.z - s; vec3 q;\n"
                          "  if (3.0 * p.x < m) q = p; else if (3.0 * p.y < m) q = vec3(p.y, p.z, p.x);\n"
                          "  else if (3.0 * p.z < m) q = vec3(p.z, p.x, p.y); else return m * 0.57735026918962576;\n"
                          "  float kk = mc_clamp(0.5 * (q.z - q.y + s), 0.0, s); return mc_length(vec3(q.x, q.y - s + kk, q.z - kk)); }"}},
    {TapeOp::octahedron_bound, {"float k_octahedron_bound(int at, vec3 p) { p = abs(p); return (p.x + p.y + p.z - K[at]) * 0.57735026918962576; }"}},
    {TapeOp::heightfield, {"", "its value noise hashes 64-bit lattice coordinates, which GLSL 4.50 has no integers for"}},
    {TapeOp::mandelbulb, {"float k_mandelbulb(int at, int extra, vec3 p) { float power = K[at]; int iterations = int(K[at + 1]);\n"
                          "  float bailout2 = K[at + 2] * K[at + 2]; vec3 w = p; float m = mc_dot(w, w);\n"
                          "  float set_radius = K[extra];\n"
                          "  float big = mc_max(abs(p.x), mc_max(abs(p.y), abs(p.z)));\n"
                          "  if (big > 8.0) return big * mc_length(p / big) - set_radius;\n"
                          "  float ball = sqrt(m) - set_radius; float dz = 1.0;\n"
                          "  for (int i = 0; i < iterations; ++i) { float r = sqrt(m); if (!(r > 0.0)) break;\n"
                          "    dz = power * pow(r, power - 1.0) * dz + 1.0;\n"
                          "    float b = power * acos(mc_clamp(w.y / r, -1.0, 1.0)); float az = power * atan(w.x, w.z);\n"
                          "    float rp = pow(r, power); w = p + vec3(sin(b) * sin(az), cos(b), sin(b) * cos(az)) * rp;\n"
                          "    m = mc_dot(w, w); if (m > bailout2) break; }\n"
                          "  if (!(m > 0.0)) return -sqrt(mc_dot(p, p));\n"
                          "  float estimate = 0.25 * log(m) * sqrt(m) / dz;\n"
                          "  return mc_dot(p, p) > 4.0 && ball < estimate ? ball : estimate; }", "", true}},
    {TapeOp::mesh, {"", "a mesh's triangles are data a shader has no place for"}},
    {TapeOp::glsl, {"", "a GLSL field is exported by pasting its own source"}},
    {TapeOp::circle, {"float k_circle(int at, vec3 p) { return mc_length(vec2(p.x - K[at], p.y - K[at + 1])) - K[at + 2]; }"}},
    {TapeOp::rect, {"float k_rect(int at, vec3 p) { vec2 d = abs(vec2(p.x - K[at], p.y - K[at + 1])) - vec2(K[at + 2], K[at + 3]);\n"
                    "  return mc_length(mc_max(d, 0.0)) + mc_min(mc_max(d.x, d.y), 0.0); }"}},
    {TapeOp::segment, {"float k_segment(int at, vec3 p) { vec2 pa = vec2(p.x - K[at], p.y - K[at + 1]); vec2 ba = vec2(K[at + 2], K[at + 3]);\n"
                       "  float h = mc_clamp(mc_dot(pa, ba) * K[at + 4], 0.0, 1.0); return mc_length(pa - ba * h) - K[at + 5]; }"}},
    {TapeOp::extrude, {"float k_extrude(int at, float d, vec3 p) { vec2 w = vec2(d, abs(p.z) - K[at]);\n"
                       "  return mc_min(mc_max(w.x, w.y), 0.0) + mc_length(mc_max(w, 0.0)); }"}},
    {TapeOp::p_revolve, {"vec3 k_p_revolve(int at, vec3 p) { return vec3(mc_length(vec2(p.x, p.z)) - K[at], p.y, 0.0); }"}},
    {TapeOp::min_, {"vec2 k_min_(int at, float a, float b) { bool take_b = b < a; return vec2(take_b ? b : a, take_b ? 1.0 : 0.0); }"}},
    {TapeOp::max_, {"vec2 k_max_(int at, float a, float b) { bool take_b = a < b; return vec2(take_b ? b : a, take_b ? 1.0 : 0.0); }"}},
    {TapeOp::subtract, {"vec2 k_subtract(int at, float a, float b) { bool take_b = a < -b; return vec2(take_b ? -b : a, take_b ? 1.0 : 0.0); }"}},
    {TapeOp::smooth_min, {"vec2 k_smooth_min(int at, float a, float b) { return vec2(mc_smooth_min(a, b, K[at]), b < a ? 1.0 : 0.0); }"}},
    {TapeOp::smooth_max, {"vec2 k_smooth_max(int at, float a, float b) { return vec2(-mc_smooth_min(-a, -b, K[at]), a < b ? 1.0 : 0.0); }"}},
    {TapeOp::smooth_subtract, {"vec2 k_smooth_subtract(int at, float a, float b) { return vec2(-mc_smooth_min(-a, b, K[at]), a < -b ? 1.0 : 0.0); }"}},
    {TapeOp::round_, {"float k_round_(int at, float d, vec3 p) { return d - K[at]; }"}},
    {TapeOp::onion, {"float k_onion(int at, float d, vec3 p) { return abs(d) - K[at]; }"}},
    {TapeOp::displace, {"float k_displace(int at, float d, vec3 p) { float f = K[at + 1];\n"
                        "  return d + K[at] * sin(f * p.x) * sin(f * p.y) * sin(f * p.z); }"}},
    {TapeOp::grid, {"float k_grid(int at, vec3 p) { int n[3]; int cell0[3]; vec3 f; float cell = K[at + 6];\n"
                    "  vec3 g = (p - vec3(K[at + 3], K[at + 4], K[at + 5])) / cell; vec3 c;\n"
                    "  for (int i = 0; i < 3; ++i) { n[i] = int(K[at + i]); c[i] = mc_clamp(g[i], 0.0, float(n[i] - 1));\n"
                    "    cell0[i] = min(int(c[i]), n[i] - 2); f[i] = c[i] - float(cell0[i]); }\n"
                    "  int s0 = at + 7 + cell0[0] + n[0] * (cell0[1] + n[1] * cell0[2]); int dy = n[0], dz = n[0] * n[1];\n"
                    "  float y0 = mc_mix(mc_mix(K[s0], K[s0 + 1], f.x), mc_mix(K[s0 + dy], K[s0 + dy + 1], f.x), f.y);\n"
                    "  float y1 = mc_mix(mc_mix(K[s0 + dz], K[s0 + dz + 1], f.x), mc_mix(K[s0 + dz + dy], K[s0 + dz + dy + 1], f.x), f.y);\n"
                    "  return mc_mix(y0, y1, f.z) + mc_length(g - c) * cell; }"}},
    {TapeOp::p_translate, {"vec3 k_p_translate(int at, vec3 p) { return p - vec3(K[at], K[at + 1], K[at + 2]); }"}},
    {TapeOp::p_affine, {"vec3 k_p_affine(int at, vec3 p) {\n"
                        "  return vec3(p.x * K[at] + p.y * K[at + 1] + p.z * K[at + 2] + K[at + 3],\n"
                        "              p.x * K[at + 4] + p.y * K[at + 5] + p.z * K[at + 6] + K[at + 7],\n"
                        "              p.x * K[at + 8] + p.y * K[at + 9] + p.z * K[at + 10] + K[at + 11]); }"}},
    {TapeOp::p_scale, {"vec3 k_p_scale(int at, vec3 p) { return p * K[at]; }"}},
    {TapeOp::scale_value, {"float k_scale_value(int at, float d, vec3 p) { return d * K[at]; }"}},
    {TapeOp::p_repeat, {"vec3 k_p_repeat(int at, vec3 p) { vec3 q = p;\n"
                        "  for (int i = 0; i < 3; ++i) { float c = K[at + i]; if (c > 0.0) q[i] = p[i] - c * mc_round(p[i] / c); }\n"
                        "  return q; }"}},
    {TapeOp::p_repeat_limited, {"vec3 k_p_repeat_limited(int at, vec3 p) { vec3 q = p;\n"
                                "  for (int i = 0; i < 3; ++i) { float c = K[at + i], n = K[at + 3 + i];\n"
                                "    if (c > 0.0) q[i] = p[i] - c * mc_clamp(mc_round(p[i] / c), -n, n); }\n"
                                "  return q; }"}},
    {TapeOp::p_mirror, {"vec3 k_p_mirror(int at, vec3 p) { vec3 q = p;\n"
                        "  for (int i = 0; i < 3; ++i) if (K[at + i] > 0.5) q[i] = abs(q[i]);\n"
                        "  return q; }"}},
    {TapeOp::p_twist, {"vec3 k_p_twist(int at, vec3 p) { float ang = K[at] * p.y; float c = cos(ang), s = sin(ang);\n"
                       "  return vec3(c * p.x - s * p.z, p.y, s * p.x + c * p.z); }"}},
    {TapeOp::p_warp, {"vec3 k_p_warp(int at, vec3 p) {\n"
                      "  return vec3(p.x - K[at] * sin(K[at + 1] * p.y), p.y - K[at + 2] * sin(K[at + 3] * p.x), p.z - K[at + 4]); }"}},
  };
  return kernels;
}
// clang-format on

}  // namespace

namespace {

// How a kernel works the stacks (tape.hpp's shapes).
enum class Shape { source, value, binary, point };
Shape shape_of(TapeOp op) {
  switch (op) {
#define MARCHCHECK_SHAPE_OF(name, shape) \
  case TapeOp::name:                    \
    return Shape::shape;
    MARCHCHECK_TAPE_KERNELS(MARCHCHECK_SHAPE_OF)
#undef MARCHCHECK_SHAPE_OF
    default: throw std::logic_error("internal: not a kernel");
  }
}

// A float as a GLSL literal that reads back as the same float: 9 significant digits.
std::string literal(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9e", static_cast<double>(v));
  return text;
}

// A kernel for one instruction: renamed, and its constants at fixed places (K[at], K[at + 2]) written as
// literals, which the evaluator reads as constants (indexing K costs an integer add and a lookup each); the
// places a loop computes still index K.
std::string specialised(const std::string& code, const std::string& name, const std::vector<float>& k,
                        std::uint32_t at) {
  std::string out = name + code.substr(code.find('('));
  out = code.substr(0, code.find("k_")) + out;
  for (size_t pos = out.find("K[at"); pos != std::string::npos; pos = out.find("K[at", pos + 1)) {
    size_t end = pos + 4, offset = 0;
    if (out[end] == ' ' && out.compare(end, 3, " + ") == 0 && std::isdigit(static_cast<unsigned char>(out[end + 3]))) {
      end += 3;
      while (std::isdigit(static_cast<unsigned char>(out[end]))) offset = offset * 10 + static_cast<size_t>(out[end++] - '0');
    }
    if (out[end] != ']') continue;  // computed: K[at + i]
    out.replace(pos, end + 1 - pos, "(" + literal(k[at + offset]) + ")");
  }
  return out;
}

// The one derived constant of a kernel with `extra` (the Mandelbulb's set radius, 2^(1 / (power - 1)) in double).
double extra_constant(const Tape& tape, const Instr& in) {
  return std::pow(2.0, 1.0 / (tape.constants[in.arg] - 1));
}

}  // namespace

std::string glsl_map(const Node& root, double time, const std::string& name) {
  const Tape tape = compile(root, time);
  std::vector<float> k(tape.constants_f.begin(), tape.constants_f.end());
  std::ostringstream kernels;  // one specialised copy per instruction
  std::ostringstream body;
  int vt = -1, pt = 0, vmax = 0, pmax = 0;
  for (const Instr& in : tape.code) {
    if (in.op == TapeOp::set_material) {
      body << "  m" << vt << " = " << in.material << ";\n";
      continue;
    }
    if (in.op == TapeOp::p_pop) {
      --pt;
      continue;
    }
    const auto found = glsl_kernels().find(in.op);
    if (found == glsl_kernels().end()) throw std::logic_error("internal: a tape kernel without its GLSL");
    const GlslKernel& kernel = found->second;
    if (!*kernel.code) throw SceneError("cannot export " + name + " as GLSL: " + kernel.why_not);
    const std::string fn = std::string(kernel.code);
    const std::string kname = fn.substr(fn.find("k_"), fn.find('(') - fn.find("k_")) + "_" +
                              std::to_string(&in - tape.code.data());
    kernels << specialised(fn, kname, k, in.arg) << "\n";
    std::string args = std::to_string(in.arg);
    if (kernel.extra) {
      args += ", " + std::to_string(k.size());
      k.push_back(static_cast<float>(extra_constant(tape, in)));
    }
    switch (shape_of(in.op)) {
      case Shape::source:
        ++vt;
        body << "  v" << vt << " = " << kname << "(" << args << ", p" << pt << "); m" << vt << " = " << in.material
             << ";\n";
        break;
      case Shape::value:
        body << "  v" << vt << " = " << kname << "(" << args << ", v" << vt << ", p" << pt << ");\n";
        break;
      case Shape::binary:
        body << "  r = " << kname << "(" << args << ", v" << vt - 1 << ", v" << vt << "); v" << vt - 1
             << " = r.x; if (r.y > 0.5) m" << vt - 1 << " = m" << vt << ";\n";
        --vt;
        break;
      case Shape::point:
        body << "  p" << pt + 1 << " = " << kname << "(" << args << ", p" << pt << ");\n";
        ++pt;
        break;
    }
    vmax = std::max(vmax, vt);
    pmax = std::max(pmax, pt);
  }
  std::ostringstream out;
  out << "// " << name << ": marchcheck's compiled field, one line an instruction (K: its constants in float).\n";
  out << "const float K[" << std::max<size_t>(k.size(), 1) << "] = float[](";
  for (size_t i = 0; i < k.size(); ++i) out << (i ? (i % 6 == 0 ? ",\n  " : ", ") : "") << literal(k[i]);
  if (k.empty()) out << "0.0";
  out << ");\n" << kHelpers;
  out << kernels.str();
  out << "// The distance, and the material of the child that decides it (-1: none) in .y.\nvec2 map(vec3 p) {\n";
  for (int i = 0; i <= vmax; ++i) out << "  float v" << i << " = 0.0; int m" << i << " = -1;\n";
  out << "  vec3 p0 = p;\n";
  for (int i = 1; i <= pmax; ++i) out << "  vec3 p" << i << " = p;\n";
  out << "  vec2 r;\n" << body.str() << "  return vec2(v0, float(m0));\n}\n";
  return out.str();
}

namespace {

std::string vec3_literal(glm::dvec3 v) {
  return "vec3(" + literal(float(v.x)) + ", " + literal(float(v.y)) + ", " + literal(float(v.z)) + ")";
}

// The camera as march::Camera makes its rays, for any iResolution: eye, basis, and focal lengths and principal
// point in units of the image height (pinhole: from the field of view; intrinsics: the scene's pixels over its
// height). No lens distortion.
std::string camera_code(const Scene& s) {
  const CameraSpec& c = s.camera;
  const double degree = std::numbers::pi / 180;
  const glm::dvec3 eye =
      c.pose == CameraPose::orbit
          ? c.target + c.distance * glm::dvec3(std::cos(c.pitch_deg * degree) * std::sin(c.yaw_deg * degree),
                                               std::sin(c.pitch_deg * degree),
                                               std::cos(c.pitch_deg * degree) * std::cos(c.yaw_deg * degree))
          : c.position;
  const bool intrinsics = c.model == CameraModel::intrinsics;
  const double f = (c.fov_full_height ? 1.0 : 0.5) / std::tan(c.fov_deg * degree * 0.5);
  const double fx = intrinsics ? c.fx / s.height : f, fy = intrinsics ? c.fy / s.height : f;
  // The principal point: the image centre (of the shader's own aspect), or the scene's, in units of its height.
  const std::string cx = intrinsics && c.cx >= 0 ? literal(float(c.cx / s.height)) : "0.5 * iResolution.x / iResolution.y";
  const std::string cy = intrinsics && c.cy >= 0 ? literal(float(c.cy / s.height)) : "0.5";
  std::ostringstream out;
  out << "  vec3 ro = " << vec3_literal(eye) << ";\n"
      << "  vec3 forward = normalize(" << vec3_literal(c.target) << " - ro);\n"
      << "  vec3 right = normalize(cross(forward, " << vec3_literal(c.up) << ")), up = cross(right, forward);\n"
      << "  vec2 at = vec2(fragCoord.x, iResolution.y - fragCoord.y) / iResolution.y;  // from the top, as marchcheck's\n"
      << "  vec2 u = vec2((at.x - " << cx << ") / " << literal(float(fx)) << ", (at.y - " << cy << ") / "
      << literal(float(fy)) << ");\n"
      << "  vec3 rd = " << (c.normalize_rays ? "normalize(forward + right * u.x - up * u.y)" : "forward + right * u.x - up * u.y")
      << ";\n";
  return out.str();
}

// Direct light as marchcheck's renderer computes it (ambient, each light's diffuse variant, darkening in shadow,
// Phong or Blinn-Phong specular, toon bands and silhouette).
std::string lighting_code(const Scene& s) {
  const Effects& e = s.effects;
  std::ostringstream out;
  out << "vec3 shade(vec3 p, vec3 n, vec3 eye, int m) {\n"
      << "  vec3 albedo = materialColor(m), to_eye = length(eye - p) > 0.0 ? normalize(eye - p) : n;\n"
      << "  vec3 col = albedo * " << literal(float(e.ambient)) << ";\n"
      << "  int model = materialSpecular(m); float strength = materialStrength(m), shininess = materialShininess(m);\n";
  const bool toon = e.shading == Shading::toon;
  if (toon)
    out << "  float bands = " << literal(float(e.toon_bands)) << ";\n";
  for (const Light& light : s.lights) {
    out << "  {\n";
    if (light.type == LightType::point)
      out << "    vec3 l = normalize(" << vec3_literal(light.position_at(s.time)) << " - p);"
          << " float dist = length(" << vec3_literal(light.position_at(s.time)) << " - p);\n";
    else
      out << "    vec3 l = -normalize(" << vec3_literal(light.direction) << "); float dist = MAX_DIST;\n";
    out << "    float cosine = dot(n, l);\n";
    if (e.diffuse == Diffuse::unclamped)
      out << "    float diffuse = cosine;\n";
    else
      out << "    float diffuse = clamp(cosine, " << literal(e.diffuse == Diffuse::floor ? float(e.diffuse_floor) : 0.0f)
          << ", 1.0);\n";
    out << "    vec3 r = -l - n * dot(n, -l) * 2.0; float base = model == 2 ? dot(n, normalize(l + to_eye)) : dot(r, to_eye);\n"
        << "    float specular = model == 0 ? 0.0 : strength * pow(clamp(base, 0.0, 1.0), shininess);\n";
    if (toon)
      out << "    diffuse = mix(0.1, 1.0, min(floor(clamp(diffuse, 0.0, 1.0) * bands), bands - 1.0) / (bands - 1.0));\n"
          << "    specular = model != 0 ? min(mix(0.1, 1.0, min(floor(clamp(specular, 0.0, 1.0) * bands), bands - 1.0)"
          << " / (bands - 1.0)), diffuse) : 0.0;\n";
    out << "    float visible = 1.0;\n";
    if (light.shadow != ShadowMode::none)
      out << "    if (cosine > 0.0 && rayMarch(p + n * SURF_DIST * 2.0, l) < dist) visible = 0.0;\n";
    out << "    col += " << vec3_literal(light.color) << " * (albedo * diffuse * mix(" << literal(float(light.darkening))
        << ", 1.0, visible) + specular * visible);\n  }\n";
  }
  if (toon) out << "  if (dot(to_eye, n) < " << literal(float(e.silhouette)) << ") col = vec3(0.0);\n";
  out << "  return col;\n}\n";
  return out.str();
}

// The scene's materials by index: colour (or its ramp colour), specular model, strength and shininess.
std::string materials_code(const Scene& s) {
  std::ostringstream color, model, strength, shininess;
  for (size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = s.materials[i];
    glm::dvec3 c = m.color;
    if (m.ramp_value >= 0 && !s.effects.ramp.empty()) {
      const auto& ramp = s.effects.ramp;
      const double x = m.ramp_value * static_cast<double>(ramp.size() - 1);
      const size_t a = std::min(static_cast<size_t>(x), ramp.size() - 1), b = std::min(a + 1, ramp.size() - 1);
      c = glm::mix(ramp[a], ramp[b], x - static_cast<double>(a));
    }
    color << "  if (m == " << i << ") return " << vec3_literal(c) << ";\n";
    model << "  if (m == " << i << ") return "
          << (m.specular == SpecularModel::none ? 0 : m.specular == SpecularModel::phong ? 1 : 2) << ";\n";
    strength << "  if (m == " << i << ") return " << literal(float(m.specular_strength)) << ";\n";
    shininess << "  if (m == " << i << ") return " << literal(float(m.shininess)) << ";\n";
  }
  return "vec3 materialColor(int m) {\n" + color.str() + "  return vec3(0.8);\n}\n" +
         "int materialSpecular(int m) {\n" + model.str() + "  return 0;\n}\n" +
         "float materialStrength(int m) {\n" + strength.str() + "  return 0.0;\n}\n" +
         "float materialShininess(int m) {\n" + shininess.str() + "  return 1.0;\n}\n";
}

}  // namespace

std::string shadertoy_shader(const Scene& scene) {
  const Scene& s = scene;
  std::ostringstream out;
  out << "// " << s.name << ", exported by marchcheck (scenes --export-glsl): paste into Shadertoy as it is.\n"
      << "// The map is the scene's compiled field; the marcher, normals, camera and direct lighting (diffuse,\n"
      << "// specular, toon, hard shadows) are the scene's. Not exported: textures, ambient occlusion, glow, fog,\n"
      << "// soft shadows, reflections, refraction, lens distortion, orthographic and frustum cameras.\n";
  out << "#define MAX_STEPS " << s.march.max_steps << "\n#define MAX_DIST " << literal(float(std::min(s.march.max_dist, 1e30)))
      << "\n#define SURF_DIST " << literal(float(s.march.hit_eps)) << "\n";
  out << glsl_map(s.root, s.time, s.name);
  const FieldInfo info = derive_info(s.root, s.time);
  // Steps of f, f / L for the scaled marcher, times the relaxation for the relaxed one (without its fallback).
  const double per_unit = (s.march.marcher == Marcher::scaled ? 1 / info.lipschitz : 1) * s.march.step_scale;
  out << "float rayMarch(vec3 ro, vec3 rd) {\n  float t = 0.0;\n  for (int i = 0; i < MAX_STEPS; i++) {\n"
      << "    float d = map(ro + rd * t).x;\n    if (abs(d) < SURF_DIST) break;\n    t += d * "
      << literal(float(per_unit)) << ";\n    if (t > MAX_DIST) break;\n  }\n  return t;\n}\n";
  out << "vec3 calcNormal(vec3 p) {\n  vec2 e = vec2(" << literal(float(s.march.normal_eps)) << ", 0.0);\n"
      << "  return normalize(vec3(map(p + e.xyy).x - map(p - e.xyy).x, map(p + e.yxy).x - map(p - e.yxy).x,\n"
      << "                        map(p + e.yyx).x - map(p - e.yyx).x));\n}\n";
  out << materials_code(s) << lighting_code(s);
  // Shadertoy shows what mainImage writes: the linear colour encoded as marchcheck's PNGs are (sRGB).
  out << "vec3 srgb(vec3 linear) {\n  vec3 c = clamp(linear, 0.0, 1.0);\n"
         "  return mix(1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, 12.92 * c, vec3(lessThanEqual(c, vec3(0.0031308))));\n}\n";
  out << "void mainImage(out vec4 fragColor, in vec2 fragCoord) {\n" << camera_code(s)
      << "  float t = rayMarch(ro, rd);\n  vec3 col = " << vec3_literal(s.effects.background) << ";\n"
      // The seed defects the renderer reproduces: a miss read as distance 0 (a hit at the ray's origin), the
      // direction taken for the eye's position.
      << (s.march.miss_as_zero ? "  if (t >= MAX_DIST) t = 0.0;\n" : "")
      << "  if (t < MAX_DIST) {\n    vec3 p = ro + rd * t;\n    col = shade(p, calcNormal(p), "
      << (s.effects.eye_is_ray_direction ? "rd" : "ro") << ", int(map(p).y));\n  }\n"
      << "  fragColor = vec4(srgb(col), 1.0);\n}\n";
  return out.str();
}

}  // namespace marchcheck::sdf
