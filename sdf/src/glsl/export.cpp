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

// A float as a GLSL literal that reads back as the same float: 9 significant digits.
std::string literal(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9e", static_cast<double>(v));
  return text;
}

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

// noise.hpp's value noise: the splitmix64 hash in 32-bit halves (GLSL ES has no 64-bit integers), the lattice
// value rounded to float as C++ rounds the double (to nearest, ties to even), smath's mix.
constexpr const char* kNoiseHelpers = R"(uvec2 mc_mul32(uint a, uint b) {  // the whole 64-bit product, (high, low)
  uint a0 = a & 0xffffu, a1 = a >> 16, b0 = b & 0xffffu, b1 = b >> 16;
  uint p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0;
  uint mid = (p00 >> 16) + (p01 & 0xffffu) + (p10 & 0xffffu);
  return uvec2(a1 * b1 + (p01 >> 16) + (p10 >> 16) + (mid >> 16), (p00 & 0xffffu) | (mid << 16));
}
uvec2 mc_mul64(uvec2 a, uvec2 b) { uvec2 r = mc_mul32(a.y, b.y); r.x += a.y * b.x + a.x * b.y; return r; }
uvec2 mc_xor_shift(uvec2 h, int s) { return h ^ uvec2(h.x >> s, (h.y >> s) | (h.x << (32 - s))); }
uvec2 mc_add1(uvec2 a) { return uvec2(a.x + (a.y == 0xffffffffu ? 1u : 0u), a.y + 1u); }
// A lattice coordinate as a 64-bit integer: floor(x) where it lies within +-4e18, else 0.
uvec2 mc_cell(float f) {
  if (!(f == f && f > -4e18 && f < 4e18)) return uvec2(0u);
  float m = abs(f), high = floor(m / 4294967296.0);  // m's low word is within its 24 bits: exact
  uvec2 v = uvec2(uint(high), uint(m - high * 4294967296.0));
  return f < 0.0 ? mc_add1(~v) : v;
}
float mc_lattice(uvec2 ix, uvec2 iz) {
  uvec2 h = mc_mul64(ix, uvec2(0x9E3779B9u, 0x7F4A7C15u)) ^ mc_mul64(iz, uvec2(0xC2B2AE3Du, 0x27D4EB4Fu));
  h = mc_mul64(mc_xor_shift(h, 30), uvec2(0xBF58476Du, 0x1CE4E5B9u));
  h = mc_mul64(mc_xor_shift(h, 27), uvec2(0x94D049BBu, 0x133111EBu));
  h = mc_xor_shift(h, 31);
  uint high = h.x >> 11, low = (h.y >> 11) | (h.x << 21);  // (h >> 11): 53 bits
  if (high == 0u && low == 0u) return 0.0;
  float scale = 5.9604644775390625e-8;  // 2^-24, halved for each place the leading bit moves up
  while ((high & 0x100000u) == 0u) { high = (high << 1) | (low >> 31); low <<= 1; scale *= 0.5; }
  uint top = (high << 3) | (low >> 29), tail = low & 0x1fffffffu;
  if (tail > 0x10000000u || (tail == 0x10000000u && (top & 1u) == 1u)) top += 1u;
  return float(top) * scale;
}
// The lee seed's hash, in float as its shader computes it (sdf::seed_sin_lattice).
float mc_seed_sin(float cx, float cz) { float s = sin(cx * 12.9898 + cz * 54.233) * 43758.5453123; return s - floor(s); }
float mc_value_noise(float x, float z, bool seedSin) {
  float fx = floor(x), fz = floor(z);
  uvec2 ix = mc_cell(fx), iz = mc_cell(fz);
  float tx = x - fx, tz = z - fz;
  float ux = tx * tx * (3.0 - 2.0 * tx), uz = tz * tz * (3.0 - 2.0 * tz);
  float a, b, c, d;
  if (seedSin) {
    a = mc_seed_sin(fx, fz), b = mc_seed_sin(fx + 1.0, fz), c = mc_seed_sin(fx, fz + 1.0), d = mc_seed_sin(fx + 1.0, fz + 1.0);
  } else {
    a = mc_lattice(ix, iz), b = mc_lattice(mc_add1(ix), iz);
    c = mc_lattice(ix, mc_add1(iz)), d = mc_lattice(mc_add1(ix), mc_add1(iz));
  }
  return mc_mix(mc_mix(a, b, ux), mc_mix(c, d, ux), uz);
}
)";

// march/texture.cpp's soil picture (512 texels square, five octaves of value noise whose lattice periods divide
// it), texel by texel, looked up as OpenImageIO does: bilinear between texel centres, wrapping.
constexpr const char* kSoilTexture = R"(vec3 mc_soil_texel(int x, int y) {
  float v = 0.0, amp = 0.5;
  for (int octave = 0; octave < 5; ++octave) {
    int cells = 8 << octave;
    float u = float(x * cells) / 512.0, w = float(y * cells) / 512.0;
    int ix = int(u), iy = int(w);
    float fx = u - float(ix), fy = w - float(iy);
    float sx = fx * fx * (3.0 - 2.0 * fx), sy = fy * fy * (3.0 - 2.0 * fy);
    uvec2 x0 = uvec2(0u, uint(ix % cells)), x1 = uvec2(0u, uint((ix + 1) % cells));
    uvec2 y0 = uvec2(0u, uint(iy % cells)), y1 = uvec2(0u, uint((iy + 1) % cells));
    float a = mc_lattice(x0, y0), b = mc_lattice(x1, y0), c = mc_lattice(x0, y1), d = mc_lattice(x1, y1);
    v += amp * ((a + (b - a) * sx) * (1.0 - sy) + (c + (d - c) * sx) * sy);
    amp *= 0.5;
  }
  return vec3(0.35 + 0.45 * v, 0.25 + 0.35 * v, 0.15 + 0.22 * v);
}
vec3 mc_soil(float s, float t) {
  vec2 x = vec2(s - floor(s), t - floor(t)) * 512.0 - 0.5, i = floor(x), f = x - i;
  int x0 = int(i.x) & 511, y0 = int(i.y) & 511, x1 = (x0 + 1) & 511, y1 = (y0 + 1) & 511;
  return mix(mix(mc_soil_texel(x0, y0), mc_soil_texel(x1, y0), f.x), mix(mc_soil_texel(x0, y1), mc_soil_texel(x1, y1), f.x), f.y);
}
)";

// mesh_distance.hpp's arithmetic for one triangle: leaf_distance2's squared distance (its candidates chosen in its
// order), closest_on_triangle's closest point and feature, face_normal and triangle_frame (glm::cross's products).
constexpr const char* kMeshHelpers = R"(vec3 mc_cross(vec3 a, vec3 b) {
  return vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}
vec3 mc_face_normal(vec3 ab, vec3 ac, vec3 bc) {
  float lab = mc_dot(ab, ab), lbc = mc_dot(bc, bc), lca = mc_dot(ac, ac);
  if (lab >= lbc && lab >= lca) return mc_cross(ac, bc);
  if (lbc >= lca) return mc_cross(ab, ac);
  return mc_cross(ab, bc);
}
float mc_triangle_distance2(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a, ac = c - a, bc = c - b, ap = p - a, bp = p - b, cp = p - c;
  float d1 = mc_dot(ab, ap), d2 = mc_dot(ac, ap), d3 = mc_dot(ab, bp), d4 = mc_dot(ac, bp);
  float d5 = mc_dot(ab, cp), d6 = mc_dot(ac, cp);
  vec3 n = mc_face_normal(ab, ac, bc);
  float vc = mc_dot(ap, mc_cross(n, ab)), vb = mc_dot(ap, mc_cross(ac, n)), va = mc_dot(bp, mc_cross(n, bc));
  vec3 q = p - n * (mc_dot(ap, n) / mc_dot(n, n));
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) q = b + bc * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) q = a + ac * (d2 / (d2 - d6));
  if (d6 >= 0.0 && d5 <= d6) q = c;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) q = a + ab * (d1 / (d1 - d3));
  if (d3 >= 0.0 && d4 <= d3) q = b;
  if (d1 <= 0.0 && d2 <= 0.0) q = a;
  vec3 d = p - q;
  return d.x * d.x + d.y * d.y + d.z * d.z;
}
// The closest point and its feature (0-2 vertices, 3 edge 01, 4 edge 12, 5 edge 20, 6 the face).
vec3 mc_closest_on_triangle(vec3 p, vec3 a, vec3 b, vec3 c, out int feature) {
  vec3 ab = b - a, ac = c - a, ap = p - a, n = mc_face_normal(ab, ac, c - b);
  float d1 = mc_dot(ab, ap), d2 = mc_dot(ac, ap);
  feature = 0; if (d1 <= 0.0 && d2 <= 0.0) return a;
  vec3 bp = p - b; float d3 = mc_dot(ab, bp), d4 = mc_dot(ac, bp);
  feature = 1; if (d3 >= 0.0 && d4 <= d3) return b;
  float vc = mc_dot(ap, mc_cross(n, ab));
  feature = 3; if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  vec3 cp = p - c; float d5 = mc_dot(ab, cp), d6 = mc_dot(ac, cp);
  feature = 2; if (d6 >= 0.0 && d5 <= d6) return c;
  float vb = mc_dot(ap, mc_cross(ac, n));
  feature = 5; if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  float va = mc_dot(bp, mc_cross(n, c - b));
  feature = 4; if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  feature = 6;
  return p - n * (mc_dot(ap, n) / mc_dot(n, n));
}
)";

// The constant space a GL driver holds before it copies constant arrays into every invocation: llvmpipe's uniform
// space, 4096 slots of 16 bytes (64 KiB). Past it a shader takes minutes to compile and to run (measured on Mesa
// 22.3: 4000 vec4 constants compile in 5 s, 4200 do not finish in 190 s), so a mesh's tables must fit in it,
// leaving room for the scene's other constants.
constexpr std::size_t kMeshConstantSlotsMax = 3840;

// Triangles per leaf of the exported search: runs of this many in the C++ search's order (halves of its leaves). The
// shader's tree is its own; the minimum over every triangle it finds is the same float whatever the leaves' size.
constexpr int kExportLeaf = 8;

// The text `line` n times, K in it replaced by 0, 1, ... n - 1.
std::string repeated(int n, const std::string& line) {
  std::string out;
  for (int k = 0; k < n; ++k) {
    std::string copy = line;
    copy.replace(copy.find('K'), 1, std::to_string(k));
    out += copy;
  }
  return out;
}

// A mesh walk's step, written out with no loop (llvmpipe ends every loop of a shader once all of them together
// have run 65535 times, so a shader's loops must be few): from box b, the next box the walk enters, its
// siblings tried around from the one `first` names (two bits per level) and taken if `accepts`, else its parent's
// next; false when the walk is over.
std::string walk_step(const std::string& name, const std::string& step, const std::string& params,
                      const std::string& accepts, int levels) {
  std::ostringstream out;
  out << "bool " << name << "_" << step << "(" << params << ", inout int b, inout int level, uint first) {\n"
      << "  bool more = false;\n";
  for (int l = 0; l < levels; ++l) {
    out << "  if (level > 0 && !more) {\n"
        << "    int c = " << name << "_LEVEL[level] + ((b - " << name << "_LEVEL[level]) & ~3);\n"
        << "    int n = min(4, " << name << "_LEVEL[level + 1] - c), f = int((first >> uint(2 * level)) & 3u);\n"
        << "    int k = b - c; bool around = false;\n";
    for (int s = 0; s < 3; ++s)
      out << "    if (!more && !around) {\n      k = (k + 1) % n; around = k == f;\n"
          << "      if (!around && " << accepts << ") { b = c + k; more = true; }\n    }\n";
    out << "    if (!more) { b = " << name << "_LEVEL[level - 1] + ((b - " << name << "_LEVEL[level]) >> 2); --level; }\n"
        << "  }\n";
  }
  out << "  return more;\n}\n";
  return out.str();
}

// A mesh's triangles in the C++ search's order, packed to fit the constant space: the vertices' floats (four to a
// slot), then 32-bit words holding each triangle's vertex indices in as many bits as the vertex count needs, then
// the boxes of a four-wide tree over runs of kExportLeaf triangles, one byte per bound on a grid over the mesh's
// box, rounded outwards by a whole cell so that a box never prunes a triangle it holds.
struct PackedMesh {
  int triangles = 0;
  std::vector<glm::vec3> vertices;
  int index_bits = 1;
  std::vector<std::uint32_t> words;
  size_t box_word = 0;           // where the boxes' bytes begin
  std::vector<int> level_start;  // each level's first box, root first, and the count of boxes
  glm::dvec3 origin, cell;       // of the boxes' grid
  size_t slots() const { return (3 * vertices.size() + 3) / 4 + (words.size() + 3) / 4; }
};

PackedMesh pack_mesh(const MeshDistance& mesh) {
  PackedMesh m;
  const auto& corners = mesh.float_corners();
  const int n = m.triangles = static_cast<int>(corners.size());
  // The vertices, shared by bit-identical corners.
  std::map<std::array<float, 3>, std::uint32_t> index_of;
  std::vector<std::uint32_t> indices;
  for (const auto& t : corners)
    for (const glm::vec3& v : t) {
      const auto [at, added] = index_of.try_emplace({v.x, v.y, v.z}, static_cast<std::uint32_t>(m.vertices.size()));
      if (added) m.vertices.push_back(v);
      indices.push_back(at->second);
    }
  while ((std::size_t{1} << m.index_bits) < m.vertices.size()) ++m.index_bits;
  // The tree's levels, root first; a box's children are the next level's 4j .. 4j + 3.
  // Grid 0..255 holds the mesh's box widened by a cell, more than the float corners' rounding out of it.
  m.cell = (mesh.bounds().hi - mesh.bounds().lo) / 252.0;
  m.origin = mesh.bounds().lo - 1.5 * m.cell;
  std::vector<std::vector<std::array<glm::dvec3, 2>>> levels(1);
  for (int first = 0; first < n; first += kExportLeaf) {
    std::array<glm::dvec3, 2> box{glm::dvec3(INFINITY), glm::dvec3(-INFINITY)};
    for (int t = first; t < std::min(n, first + kExportLeaf); ++t)
      for (const glm::vec3& v : corners[static_cast<size_t>(t)])
        box = {glm::min(box[0], glm::dvec3(v)), glm::max(box[1], glm::dvec3(v))};
    levels[0].push_back(box);
  }
  while (levels.front().size() > 1) {
    std::vector<std::array<glm::dvec3, 2>> up;
    for (size_t j = 0; j < levels.front().size(); j += 4) {
      std::array<glm::dvec3, 2> box = levels.front()[j];
      for (size_t k = j + 1; k < std::min(j + 4, levels.front().size()); ++k)
        box = {glm::min(box[0], levels.front()[k][0]), glm::max(box[1], levels.front()[k][1])};
      up.push_back(box);
    }
    levels.insert(levels.begin(), up);
  }
  // The words: indices, then the box bytes (lo x y z, hi x y z), level by level.
  m.words.assign((indices.size() * static_cast<size_t>(m.index_bits) + 31) / 32, 0u);
  for (size_t k = 0; k < indices.size(); ++k) {
    const size_t bit = k * static_cast<size_t>(m.index_bits);
    m.words[bit / 32] |= indices[k] << (bit % 32);
    if (bit % 32 + static_cast<size_t>(m.index_bits) > 32) m.words[bit / 32 + 1] |= indices[k] >> (32 - bit % 32);
  }
  m.box_word = m.words.size();
  size_t bytes = 0;
  for (const auto& level : levels) {
    m.level_start.push_back(static_cast<int>(bytes / 6));
    for (const auto& box : level)
      for (int side = 0; side < 2; ++side)
        for (int i = 0; i < 3; ++i) {
          const double at = (box[static_cast<size_t>(side)][i] - m.origin[i]) / m.cell[i];
          const auto q = static_cast<std::uint32_t>(side == 0 ? std::floor(at) - 1 : std::ceil(at) + 1);
          if (bytes % 4 == 0) m.words.push_back(0);
          m.words.back() |= q << (8 * (bytes % 4));
          ++bytes;
        }
  }
  m.level_start.push_back(static_cast<int>(bytes / 6));
  return m;
}

// One mesh's kernel over its packed triangles (NAME_P the vertices, NAME_W the words). The distance is the C++
// search's: the smallest squared distance over every triangle by leaf_distance2's arithmetic, so the same float.
// The sign is the closest face's normal where the closest point lies inside a face, and otherwise the parity of a
// ray's crossings: the pseudonormals the C++ sign uses do not fit. Both give the C++ sign except within rounding of
// the surface.
std::string mesh_kernel(const MeshDistance& mesh, const std::string& name, const std::string& scene) {
  const PackedMesh m = pack_mesh(mesh);
  const int n = m.triangles, leaf_level = static_cast<int>(m.level_start.size()) - 2;
  if (m.slots() > kMeshConstantSlotsMax)
    throw SceneError("cannot export " + scene + " as GLSL: its mesh of " + std::to_string(n) + " triangles needs " +
                     std::to_string(m.slots()) + " constant slots of 16 bytes, more than the " +
                     std::to_string(kMeshConstantSlotsMax) + " a GL driver holds beside the scene's other constants");
  // The first triangle of leaf box b.
  const std::string leaf_first = "      int from = (b - " +
                                 std::to_string(m.level_start[static_cast<size_t>(leaf_level)]) + ") * " +
                                 std::to_string(kExportLeaf) + ";\n";
  std::ostringstream out;
  out << "const vec4 " << name << "_P[" << (3 * m.vertices.size() + 3) / 4 << "] = vec4[](";
  for (size_t f = 0; f < 3 * m.vertices.size(); f += 4) {
    out << (f ? ",\n  " : "") << "vec4(";
    for (size_t k = f; k < f + 4; ++k) {
      const float value = k < 3 * m.vertices.size() ? m.vertices[k / 3][static_cast<int>(k % 3)] : 0.0f;
      out << (k > f ? ", " : "") << literal(value);
    }
    out << ")";
  }
  out << ");\nconst uvec4 " << name << "_W[" << (m.words.size() + 3) / 4 << "] = uvec4[](";
  for (size_t w = 0; w < m.words.size(); w += 4) {
    out << (w ? ",\n  " : "") << "uvec4(";
    for (size_t k = w; k < w + 4; ++k) out << (k > w ? ", " : "") << (k < m.words.size() ? m.words[k] : 0u) << "u";
    out << ")";
  }
  out << ");\nconst int " << name << "_LEVEL[" << m.level_start.size() << "] = int[](";
  for (size_t l = 0; l < m.level_start.size(); ++l) out << (l ? ", " : "") << m.level_start[l];
  auto vec3_of = [](glm::dvec3 v) {
    return "vec3(" + literal(float(v.x)) + ", " + literal(float(v.y)) + ", " + literal(float(v.z)) + ")";
  };
  out << ");\nuint " << name << "_word(int i) { return " << name << "_W[i >> 2][i & 3]; }\n"
      << "vec3 " << name << "_corner(int t, int k) {\n"
      << "  int bit = (3 * t + k) * " << m.index_bits << ", s = bit & 31;\n"
      << "  uint w = " << name << "_word(bit >> 5) >> uint(s);\n"
      << "  if (s + " << m.index_bits << " > 32) w |= " << name << "_word((bit >> 5) + 1) << uint(32 - s);\n"
      << "  int f = 3 * int(w & " << ((1u << m.index_bits) - 1) << "u);\n"
      << "  return vec3(" << name << "_P[f >> 2][f & 3], " << name << "_P[(f + 1) >> 2][(f + 1) & 3], " << name
      << "_P[(f + 2) >> 2][(f + 2) & 3]);\n}\n"
      << "float " << name << "_byte(int at) {\n  return float((" << name << "_word(" << m.box_word
      << " + (at >> 2)) >> uint(8 * (at & 3))) & 255u);\n}\n"
      << "void " << name << "_box(int b, out vec3 lo, out vec3 hi) {\n"
      << "  lo = " << vec3_of(m.origin) << " + vec3(" << name << "_byte(6 * b), " << name << "_byte(6 * b + 1), " << name
      << "_byte(6 * b + 2)) * " << vec3_of(m.cell) << ";\n"
      << "  hi = " << vec3_of(m.origin) << " + vec3(" << name << "_byte(6 * b + 3), " << name << "_byte(6 * b + 4), "
      << name << "_byte(6 * b + 5)) * " << vec3_of(m.cell) << ";\n}\n"
      << "float " << name << "_box_distance2(vec3 p, int b) {\n  vec3 lo, hi; " << name << "_box(b, lo, hi);\n"
      << "  vec3 d = max(max(lo - p, p - hi), vec3(0.0));\n  return mc_dot(d, d);\n}\n"
      // The ray's direction avoids the axes and diagonals meshes are built on.
      << "const vec3 " << name << "_DIR = vec3(0.5362, 0.7174, 0.4450);\n"
      << "bool " << name << "_crosses(vec3 p, int b) {\n  vec3 lo, hi; " << name << "_box(b, lo, hi);\n"
      << "  vec3 t0 = (lo - p) / " << name << "_DIR, t1 = (hi - p) / " << name << "_DIR;\n"
      << "  vec3 tn = min(t0, t1), tf = max(t0, t1);\n"
      << "  return max(max(tn.x, tn.y), max(tn.z, 0.0)) <= min(min(tf.x, tf.y), tf.z);\n}\n"
      << "void " << name << "_try(vec3 p, int t, inout float best2, inout int best) {\n"
      << "  if (t >= " << n << ") return;\n"
      << "  float d2 = mc_triangle_distance2(p, " << name << "_corner(t, 0), " << name << "_corner(t, 1), " << name
      << "_corner(t, 2));\n  if (d2 < best2) { best2 = d2; best = t; }\n}\n"
      << "void " << name << "_cross(vec3 p, int t, inout int crossings) {\n"
      << "  if (t >= " << n << ") return;\n"
      << "  vec3 a = " << name << "_corner(t, 0), e1 = " << name << "_corner(t, 1) - a, e2 = " << name
      << "_corner(t, 2) - a;\n"
      << "  vec3 h = cross(" << name << "_DIR, e2), s = p - a, q = cross(s, e1); float det = mc_dot(e1, h);\n"
      << "  if (det == 0.0) return;\n"
      << "  float u = mc_dot(s, h) / det, v = mc_dot(" << name << "_DIR, q) / det;\n"
      << "  if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && mc_dot(e2, q) / det > 0.0) ++crossings;\n}\n"
      << "void " << name << "_nearer(vec3 p, int c, int k, int n, inout float e0, inout int k0) {\n"
      << "  if (k >= n) return;\n  float e = " << name << "_box_distance2(p, c + k);\n"
      << "  if (e < e0) { e0 = e; k0 = k; }\n}\n"
      << walk_step(name, "closest", "vec3 p, float best2", name + "_box_distance2(p, c + k) < best2", leaf_level)
      << walk_step(name, "crossing", "vec3 p", name + "_crosses(p, c + k)", leaf_level)
      // Odd crossings: inside.
      << "bool " << name << "_inside(vec3 p) {\n"
      << "  int b = 0, level = 0, crossings = 0;\n"
      << "  for (bool walking = " << name << "_crosses(p, 0); walking;) {\n"
      << "    if (level < " << leaf_level << ") {\n"
      << "      b = " << name << "_LEVEL[level + 1] + 4 * (b - " << name << "_LEVEL[level]); ++level;\n"
      << "      if (" << name << "_crosses(p, b)) continue;\n"
      << "    } else {\n"
      << leaf_first
      << repeated(kExportLeaf, "      " + name + "_cross(p, from + K, crossings);\n")
      << "    }\n"
      << "    walking = " << name << "_crossing(p, b, level, 0u);\n  }\n"
      << "  return (crossings & 1) == 1;\n}\n"
      // The closest triangle: each box's nearest child first, boxes no nearer than the best found skipped.
      << "float " << name << "(vec3 p) {\n"
      << "  float best2 = uintBitsToFloat(0x7f800000u); int best = 0;  // infinity\n"
      << "  int b = 0, level = 0; uint first = 0u;\n"
      << "  for (bool walking = true; walking;) {\n"
      << "    if (level < " << leaf_level << ") {\n"
      << "      int c = " << name << "_LEVEL[level + 1] + 4 * (b - " << name << "_LEVEL[level]);\n"
      << "      int n = min(4, " << name << "_LEVEL[level + 2] - c), k0 = 0; float e0 = " << name
      << "_box_distance2(p, c);\n"
      << repeated(3, "      " + name + "_nearer(p, c, K + 1, n, e0, k0);\n")
      << "      ++level; b = c + k0;\n"
      << "      first = (first & ~(3u << uint(2 * level))) | (uint(k0) << uint(2 * level));\n"
      << "      if (e0 < best2) continue;\n"
      << "    } else {\n"
      << leaf_first
      << repeated(kExportLeaf, "      " + name + "_try(p, from + K, best2, best);\n")
      << "    }\n"
      << "    walking = " << name << "_closest(p, best2, b, level, first);\n  }\n"
      << "  vec3 a = " << name << "_corner(best, 0), bb = " << name << "_corner(best, 1), c = " << name
      << "_corner(best, 2);\n"
      << "  int feature; vec3 q = mc_closest_on_triangle(p, a, bb, c, feature);\n"
      << "  bool inside = feature == 6 ? mc_dot(p - q, cross(bb - a, c - a)) < 0.0 : " << name << "_inside(p);\n"
      << "  return (inside ? -1.0 : 1.0) * sqrt(best2);\n}\n";
  return out.str();
}

// Each kernel's GLSL: the C++ kernel's expressions, K[at + i] for its k(i). Empty: not exportable (why).
struct GlslKernel {
  const char* code;
  const char* why_not = "";
  bool extra = false;          // also takes one constant the C++ kernel derives in double (its index in K)
  const char* helpers = "";    // written once before the kernels, where a tape uses this one
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
    {TapeOp::heightfield, {"float k_heightfield(int at, vec3 p) { int pairs = int(K[at]); bool seedSin = K[at + 1] != 0.0;\n"
                           "  float h = 0.0;\n"
                           "  for (int i = 0; i < pairs; ++i) h += K[at + 2 + 2 * i] * mc_value_noise(p.x * K[at + 3 + 2 * i], p.z * K[at + 3 + 2 * i], seedSin);\n"
                           "  return p.y - h; }", "", false, kNoiseHelpers}},
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
    {TapeOp::mesh, {"", "", false, kMeshHelpers}},  // written per mesh: mesh_kernel
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
  std::string helpers;  // the kernels' own, once each
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
    if (*kernel.why_not) throw SceneError("cannot export " + name + " as GLSL: " + kernel.why_not);
    if (in.op == TapeOp::mesh) {  // its data is the kernel
      const std::string kname = "k_mesh_" + std::to_string(&in - tape.code.data());
      if (helpers.find(kernel.helpers) == std::string::npos) helpers += kernel.helpers;
      kernels << mesh_kernel(*tape.meshes[in.arg], kname, name);
      ++vt;
      body << "  v" << vt << " = " << kname << "(p" << pt << "); m" << vt << " = " << in.material << ";\n";
      vmax = std::max(vmax, vt);
      continue;
    }
    const std::string fn = std::string(kernel.code);
    std::string kname = fn.substr(fn.find("k_"), fn.find('(') - fn.find("k_"));
    if (kname.back() == '_') kname.pop_back();  // GLSL reserves names with "__"
    kname += "_" + std::to_string(&in - tape.code.data());
    if (*kernel.helpers && helpers.find(kernel.helpers) == std::string::npos) helpers += kernel.helpers;
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
  out << ");\n" << kHelpers << helpers;
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

// Focal length in units of the image height, as march::Camera derives it (pinhole, frustum: from the field of
// view; intrinsics: the scene's pixels over its height).
double focal_over_height(const Scene& s) {
  const CameraSpec& c = s.camera;
  if (c.model == CameraModel::intrinsics) return c.fy / s.height;
  return (c.fov_full_height ? 1.0 : 0.5) / std::tan(c.fov_deg * std::numbers::pi / 180 * 0.5);
}

// The camera as march::Camera makes its rays, for any iResolution (pixel centres counted from the top, as
// marchcheck's): its eye and basis, then each model's ray; intrinsics undistort with Newton's steps as it does (or,
// with a shader's lens, distort).
std::string camera_code(const Scene& s) {
  const CameraSpec& c = s.camera;
  const double degree = std::numbers::pi / 180;
  const glm::dvec3 eye = camera_frame(c).eye;
  const bool shader_lens = c.lens == LensConvention::shader;
  std::ostringstream out;
  if (c.model == CameraModel::intrinsics) {
    const LensCoefficients lens = image_lens(c);
    const std::string k1 = literal(float(lens.k1)), k2 = literal(float(lens.k2)), p1 = literal(float(lens.p1)),
                      p2 = literal(float(lens.p2));
    out << "// Brown-Conrady distortion and its Jacobian columns; undistort inverts it by Newton's method.\n"
        << "vec2 distort(vec2 u, out vec2 jx, out vec2 jy) {\n"
        << "  float r2 = u.x * u.x + u.y * u.y, radial = 1.0 + " << k1 << " * r2 + " << k2 << " * r2 * r2;\n"
        << "  float dr = 2.0 * (" << k1 << " + 2.0 * " << k2 << " * r2);\n"
        << "  jx = vec2(radial + u.x * dr * u.x + 2.0 * " << p1 << " * u.y + 6.0 * " << p2 << " * u.x,\n"
        << "            u.y * dr * u.x + 2.0 * " << p1 << " * u.x + 2.0 * " << p2 << " * u.y);\n"
        << "  jy = vec2(u.x * dr * u.y + 2.0 * " << p1 << " * u.x + 2.0 * " << p2 << " * u.y,\n"
        << "            radial + u.y * dr * u.y + 6.0 * " << p1 << " * u.y + 2.0 * " << p2 << " * u.x);\n"
        << "  return vec2(u.x * radial + 2.0 * " << p1 << " * u.x * u.y + " << p2 << " * (r2 + 2.0 * u.x * u.x),\n"
        << "              u.y * radial + " << p1 << " * (r2 + 2.0 * u.y * u.y) + 2.0 * " << p2 << " * u.x * u.y);\n}\n"
        << "vec2 undistort(vec2 d) {\n  vec2 u = d, jx, jy;\n  for (int i = 0; i < 30; i++) {\n"
        << "    vec2 r = distort(u, jx, jy) - d; float det = jx.x * jy.y - jy.x * jx.y;\n"
        << "    if (abs(r.x) + abs(r.y) == 0.0 || det == 0.0) break;\n"
        << "    u -= vec2(jy.y * r.x - jy.x * r.y, -jx.y * r.x + jx.x * r.y) / det;\n  }\n  return u;\n}\n";
  }
  out << "void cameraRay(vec2 fragCoord, out vec3 ro, out vec3 rd) {\n"
      << "  vec3 eye = " << vec3_literal(eye) << ";\n"
      << "  vec3 forward = normalize(" << vec3_literal(c.target) << " - eye);\n"
      << (c.axes == CameraAxes::shader
              ? "  vec3 right = normalize(cross(" + vec3_literal(c.up) + ", forward)), up = cross(forward, right);\n"
              : "  vec3 right = normalize(cross(forward, " + vec3_literal(c.up) + ")), up = cross(right, forward);\n")
      << "  vec2 px = vec2(fragCoord.x, iResolution.y - fragCoord.y);  // from the top, as marchcheck's\n";
  switch (c.model) {
    case CameraModel::orthographic:
      out << "  float unit = " << literal(float(c.ortho_height)) << " / iResolution.y;\n"
          << "  ro = eye + right * ((px.x - iResolution.x * 0.5) * unit) - up * ((px.y - iResolution.y * 0.5) * unit);\n"
          << "  rd = forward;\n}\n";
      return out.str();
    case CameraModel::frustum:
      out << "  float th = " << literal(float(std::tan(c.fov_deg * degree * 0.5))) << ", tw = th * iResolution.x / iResolution.y;\n"
          << "  vec2 uv = px / iResolution.xy;\n"
          << "  vec3 top = mix(forward - right * tw + up * th, forward + right * tw + up * th, uv.x);\n"
          << "  vec3 bottom = mix(forward - right * tw - up * th, forward + right * tw - up * th, uv.x);\n"
          << "  ro = eye;\n  rd = normalize(mix(top, bottom, uv.y));\n}\n";
      return out.str();
    default: break;
  }
  // Focal lengths and principal point in units of the image height: the image centre of the shader's own aspect,
  // or the scene's.
  const bool intrinsics = c.model == CameraModel::intrinsics;
  const double fx = intrinsics ? c.fx / s.height : focal_over_height(s), fy = focal_over_height(s);
  const std::string cx = intrinsics && c.cx >= 0 ? literal(float(c.cx / s.height)) : "0.5 * iResolution.x / iResolution.y";
  const std::string cy = intrinsics && c.cy >= 0 ? literal(float(c.cy / s.height)) : "0.5";
  out << "  vec2 at = px / iResolution.y;\n"
      << "  vec2 u = vec2((at.x - " << cx << ") / " << literal(float(fx)) << ", (at.y - " << cy << ") / "
      << literal(float(fy)) << ");\n";
  if (intrinsics) out << (shader_lens ? "  vec2 jx, jy;\n  u = distort(u, jx, jy);\n" : "  u = undistort(u);\n");
  out << "  ro = eye;\n  rd = " << (c.normalize_rays ? "normalize(forward + right * u.x - up * u.y)" : "forward + right * u.x - up * u.y")
      << ";\n}\n";
  return out.str();
}

// The hit threshold at t (march::hit_threshold): absolute, relative to t, or the camera's pixel footprint.
std::string hit_eps_code(const Scene& s) {
  std::string eps = "SURF_DIST";
  if (s.march.eps_mode == EpsMode::relative) eps = "SURF_DIST * t";
  if (s.march.eps_mode == EpsMode::pixel)
    eps = s.camera.model == CameraModel::orthographic
              ? literal(float(0.5 * s.camera.ortho_height)) + " / iResolution.y"
              : literal(float(0.5 / focal_over_height(s))) + " / iResolution.y * t";
  return "float hitEps(float t) { return " + eps + "; }\n";
}

// How far a step goes per unit of f (sdf::step_per_unit_f with the scene's declared L). Marches and soft shadows
// step by it.
double step_per_unit_f(const Scene& s) { return step_per_unit_f(s.march, derive_info(s.root, s.time).lipschitz); }

// The scene's marcher as march::march runs it, outcome for outcome: sphere tracing in steps of f (scaled: f / L,
// relaxed: over-relaxed steps of f / L with Keinert et al.'s fallback), or fixed steps with bisection of the crossing.
std::string marcher_code(const Scene& s) {
  const MarchSettings& m = s.march;
  std::ostringstream out;
  if (m.clip == Clip::bounds)
    out << "// clip=bounds is not exported: this march covers the whole ray to maxDist (the same hits, more steps).\n";
  if (m.step_bound == StepBound::perturbed)
    out << "// step_bound=perturbed is not exported: this march steps by f / L alone (the same hits, more steps).\n";
  out << "// outcome: 0 hit, 1 past maxDist, 2 out of steps, 3 started inside, 4 not finite; minAbsF: smallest |f|.\n"
      << "struct March { float t; int steps; float minAbsF; int outcome; };\n"
      << hit_eps_code(s)
      << "// side: 1 outside the surface, -1 inside it (the field negated, as refraction marches through a solid).\n"
      << "float probe(inout March r, vec3 ro, vec3 rd, float t, float side) {\n"
      << "  float v = side * map(ro + rd * t).x; r.steps++; r.t = t;\n"
      << "  if (abs(v) < r.minAbsF) r.minAbsF = abs(v);\n  return v;\n}\n"
      << "March march(vec3 ro, vec3 rd, float maxDist, float side) {\n"
      << "  March r = March(0.0, 0, 1e38, 2);\n";
  if (m.marcher == Marcher::fixed) {
    out << "  float t = 0.0, prevT = 0.0;\n  while (r.steps < MAX_STEPS) {\n"
        << "    float v = probe(r, ro, rd, t, side), eps = hitEps(t);\n"
        << "    if (isnan(v) || isinf(v)) { r.outcome = 4; return r; }\n"
        << "    if (r.steps == 1 && v < -eps) { r.outcome = 3; return r; }\n"
        << "    if (v < eps) {\n      if (v > -eps || r.steps == 1) { r.outcome = 0; return r; }\n"
        << "      float lo = prevT, hi = t;  // crossed between prevT (outside) and t (inside)\n"
        << "      while (r.steps < MAX_STEPS) {\n        float mid = lo + (hi - lo) * 0.5, vm = probe(r, ro, rd, mid, side);\n"
        << "        if (isnan(vm) || isinf(vm)) { r.outcome = 4; return r; }\n"
        << "        if (abs(vm) < hitEps(mid) || !(mid > lo && mid < hi)) { r.outcome = 0; return r; }\n"
        << "        if (vm > 0.0) lo = mid; else hi = mid;\n      }\n      r.t = lo; return r;\n    }\n"
        << "    prevT = t;\n    t += " << literal(float(m.fixed_step)) << ";\n"
        << "    if (t > maxDist) { r.t = t; r.outcome = 1; return r; }\n  }\n  r.t = t;\n  return r;\n}\n";
    return out.str();
  }
  const double lipschitz = derive_info(s.root, s.time).lipschitz;
  out << "  float t = 0.0, omega = " << literal(m.marcher == Marcher::relaxed ? float(m.relaxation) : 1.0f)
      << ", prevT = 0.0, prevF = 0.0, prevStep = 0.0;\n  const float scale = "
      << literal(float(step_per_unit_f(m, lipschitz))) << ", radius = " << literal(float(1 / lipschitz))
      << ";  // radius: 1 / L\n"
      << "  while (r.steps < MAX_STEPS) {\n    float v = probe(r, ro, rd, t, side), eps = hitEps(t);\n"
      << "    if (isnan(v) || isinf(v)) { r.outcome = 4; return r; }\n"
      << "    if (r.steps == 1 && v < -eps) { r.outcome = 3; return r; }\n"
      << "    if (omega > 1.0 && (abs(v) + prevF) * radius < prevStep) {  // the spheres do not overlap: step back\n"
      << "      omega = 1.0; t = prevT + prevF * scale; prevStep = prevF * scale;\n"
      << "    } else {\n      if (v < eps) {\n"
      << (m.refine == HitRefine::secant
              ? "        // secant_root: one Newton step through the last two samples, kept where |f| is smaller there\n"
                "        float dt = t - prevT, df = prevF - v, root = t + v * dt / df;\n"
                "        if (r.steps > 1 && r.steps < MAX_STEPS && df > 0.0 && dt > 0.0 && !isinf(root) &&\n"
                "            !isnan(root) && root != t && !(abs(probe(r, ro, rd, root, side)) < abs(v))) r.t = t;\n"
              : "")
      << "        r.outcome = 0; return r;\n      }\n"
      << "      float step = v * omega * scale, plainReach = t + v * scale;\n"
      << "      prevT = t; prevF = v; prevStep = step; t += step;\n"
      << "      // an over-relaxed step past maxDist may yet be stepped back: a miss where a plain step passes it too\n"
      << "      if (t > maxDist && plainReach > maxDist) { r.t = t; r.outcome = 1; return r; }\n    }\n  }\n"
      << "  r.t = t;\n  return r;\n}\n";
  return out.str();
}

// Normals by the scene's method (analytic, which needs dual numbers, by central differences).
std::string normal_code(const Scene& s) {
  const MarchSettings& m = s.march;
  std::ostringstream out;
  out << "vec3 unitOrZero(vec3 g) { float len = sqrt(dot(g, g)); return len > 0.0 && !isinf(len) ? g / len : vec3(0.0); }\n"
      << "vec3 calcNormal(vec3 p, float t) {\n  float e = "
      << (m.normal_eps_scaled ? literal(float(m.normal_eps)) + " * t" : literal(float(m.normal_eps))) << ";\n";
  if (m.normal == NormalMethod::forward)
    out << "  float f0 = map(p).x;\n"
        << "  return unitOrZero(vec3(map(p + vec3(e, 0, 0)).x - f0, map(p + vec3(0, e, 0)).x - f0, map(p + vec3(0, 0, e)).x - f0));\n";
  else if (m.normal == NormalMethod::tetra)
    out << "  vec3 k0 = vec3(1, -1, -1), k1 = vec3(-1, -1, 1), k2 = vec3(-1, 1, -1), k3 = vec3(1);\n"
        << "  return unitOrZero(k0 * map(p + k0 * e).x + k1 * map(p + k1 * e).x + k2 * map(p + k2 * e).x +\n"
        << "                    k3 * map(p + k3 * e).x);\n";
  else
    out << "  return unitOrZero(vec3(map(p + vec3(e, 0, 0)).x - map(p - vec3(e, 0, 0)).x,\n"
        << "                        map(p + vec3(0, e, 0)).x - map(p - vec3(0, e, 0)).x,\n"
        << "                        map(p + vec3(0, 0, e)).x - map(p - vec3(0, 0, e)).x));\n";
  out << "}\nvec3 calcNormal(vec3 p) { return calcNormal(p, 1.0); }\n";
  return out.str();
}

// The scene's triangle meshes (the Unity seed's depth-buffer occlusion): the nearest triangle along the ray, its
// normal facing the ray and its material; the march stops there. Empty without meshes.
std::string meshes_code(const Scene& s) {
  if (s.meshes.empty()) return "";
  std::ostringstream corners, materials;
  size_t n = 0;
  for (const SceneMesh& mesh : s.meshes)
    for (const auto& tri : mesh.triangles) {
      for (std::uint32_t v : tri) corners << (n ? ",\n  " : "") << vec3_literal(mesh.vertices[v]), ++n;
      materials << (n > 3 ? ", " : "") << mesh.material;
    }
  std::ostringstream out;
  out << "const vec3 TRIANGLES[" << n << "] = vec3[](" << corners.str() << ");\n"
      << "const int TRIANGLE_MATERIAL[" << n / 3 << "] = int[](" << materials.str() << ");\n"
      << "struct MeshHit { bool hit; float t; vec3 normal; int material; };\n"
      << "MeshHit meshHit(vec3 ro, vec3 rd, float maxT) {  // Moller-Trumbore, either face\n"
      << "  MeshHit h = MeshHit(false, maxT, vec3(0.0), -1);\n"
      << "  for (int i = 0; i < " << n / 3 << "; i++) {\n"
      << "    vec3 a = TRIANGLES[3 * i], e1 = TRIANGLES[3 * i + 1] - a, e2 = TRIANGLES[3 * i + 2] - a;\n"
      << "    vec3 q = cross(rd, e2); float det = dot(e1, q);\n    if (det == 0.0) continue;\n"
      << "    vec3 s = ro - a; float u = dot(s, q) / det; vec3 w = cross(s, e1); float v = dot(rd, w) / det;\n"
      << "    float t = dot(e2, w) / det;\n"
      << "    if (u < 0.0 || v < 0.0 || u + v > 1.0 || !(t > 0.0) || t >= h.t) continue;\n"
      << "    vec3 ng = normalize(cross(e1, e2));\n"
      << "    h = MeshHit(true, t, dot(ng, rd) > 0.0 ? -ng : ng, TRIANGLE_MATERIAL[i]);\n  }\n  return h;\n}\n";
  return out.str();
}

// Each light's visibility from surface point p (hit at t along its ray), as march::shadow_visibility: hard shadows
// start where the light's bias puts them and count hits and starts inside; soft ones take the penumbra of the
// closest approach (classic, or improved by the previous step's sphere).
std::string shadow_code(const Light& light) {
  if (light.shadow == ShadowMode::none) return "1.0";
  const std::string bias = literal(float(light.bias_factor));
  std::ostringstream out;
  out << "shadowOf(p, n, l, dist, t, " << static_cast<int>(light.shadow == ShadowMode::soft)
      << ", " << static_cast<int>(light.bias) << ", " << bias << ", "
      << static_cast<int>(light.soft == SoftShadow::improved) << ", " << literal(float(light.penumbra)) << ")";
  return out.str();
}

std::string shadow_functions(const Scene& s) {
  std::ostringstream out;
  out << "// bias: 0 lifted by bias hit thresholds, 1 lifted by one and hits nearer than bias thresholds ignored,\n"
      << "// 2 above the threshold and the rounding of |p| and t; improved: 0 for Quilez's classic penumbra.\n"
      << "float shadowOf(vec3 p, vec3 n, vec3 l, float dist, float t, int soft, int bias, float factor, int improved,\n"
      << "               float penumbra) {\n"
      << "  float eps = hitEps(t), offset = bias == 0 ? eps * factor : eps;\n"
      << "  if (bias == 2) offset = 2.0 * eps + factor * 1.1920929e-7 * (max(max(abs(p.x), abs(p.y)), abs(p.z)) + t);\n"
      << "  vec3 o = p + n * offset; float far = min(MAX_DIST, dist);\n"
      << "  if (soft == 0) {\n    March r = march(o, l, far, 1.0);\n"
      << "    bool blocked = r.outcome == 0 || r.outcome == 3;\n"
      << "    if (bias == 1 && r.t <= factor * eps) blocked = false;\n    return blocked ? 0.0 : 1.0;\n  }\n"
      << "  float res = 1.0, s = 0.0, prevH = 3.4e38;\n"
      << "  for (int i = 0; i < MAX_STEPS && s < far; ++i) {\n    float h = map(o + l * s).x;\n"
      << "    if (isnan(h) || isinf(h)) break;\n    if (h < eps) { res = 0.0; break; }\n"
      << "    if (improved == 0 || i == 0) {\n      res = min(res, penumbra * h / max(s, eps));\n    } else {\n"
      << "      float y = h * h / (2.0 * prevH), d = sqrt(max(h * h - y * y, 0.0));\n"
      << "      res = min(res, penumbra * d / max(0.0, s - y));\n    }\n"
      << "    prevH = h;\n    s += h * " << literal(float(step_per_unit_f(s))) << ";\n  }\n  return clamp(res, 0.0, 1.0);\n}\n";
  return out.str();
}

// Ambient occlusion by samples along the normal (march's ambient_occlusion), 1 for the other kinds.
std::string occlusion_code(const Scene& s) {
  const Effects& e = s.effects;
  std::ostringstream out;
  out << "float occlusion(vec3 p, vec3 n) {\n";
  if (e.ao == AmbientOcclusion::samples)
    out << "  float occluded = 0.0, weights = 0.0, weight = 1.0;\n"
        << "  for (int i = 1; i <= " << e.ao_samples << "; i++) {\n"
        << "    float h = " << literal(float(e.ao_distance)) << " * float(i) / " << e.ao_samples << ".0;\n"
        << "    occluded += weight * clamp((h - map(p + n * h).x) / h, 0.0, 1.0); weights += weight; weight *= 0.85;\n"
        << "  }\n  return 1.0 - occluded / weights;\n";
  else
    out << "  return 1.0;\n";
  out << "}\n";
  return out.str();
}

// Direct light as marchcheck's renderer computes it (ambient times occlusion, each light's diffuse variant,
// darkening in shadow, Phong or Blinn-Phong specular, toon bands and silhouette).
std::string lighting_code(const Scene& s) {
  const Effects& e = s.effects;
  std::ostringstream out;
  out << "vec3 shade(vec3 p, vec3 n, vec3 eye, int m, float t, float ao) {\n"
      << "  vec3 albedo = materialColor(m, p, n), to_eye = length(eye - p) > 0.0 ? normalize(eye - p) : n;\n"
      << "  vec3 col = albedo * " << literal(float(e.ambient)) << " * ao;\n"
      << "  int model = materialSpecular(m); float strength = materialStrength(m), shininess = materialShininess(m);\n";
  const bool toon = e.shading == Shading::toon;
  if (toon) out << "  float bands = " << literal(float(e.toon_bands)) << ";\n";
  for (const Light& light : s.lights) {
    out << "  {\n";
    if (light.type == LightType::point)
      out << "    vec3 l = " << vec3_literal(light.position_at(s.time)) << " - p; float dist = length(l); l /= dist;\n";
    else
      out << "    vec3 l = -normalize(" << vec3_literal(light.direction) << "); float dist = 3.4e38;\n";
    out << "    float cosine = dot(n, l);\n";
    if (e.diffuse == Diffuse::unclamped)
      out << "    float diffuse = cosine;\n";
    else
      out << "    float diffuse = clamp(cosine, " << literal(e.diffuse == Diffuse::floor ? float(e.diffuse_floor) : 0.0f)
          << ", 1.0);\n";
    out << "    vec3 r = -l - n * dot(n, -l) * 2.0; float base = model == 2 ? dot(n, normalize(l + to_eye)) : dot(r, to_eye);\n"
        << "    float specular = model == 0 ? 0.0 : strength * pow(clamp(base, 0.0, 1.0), shininess);\n";
    if (toon)
      out << "    diffuse = mix(0.1, 1.0, mod(floor(clamp(diffuse, 0.0, 1.0) * bands), bands) / (bands - 1.0));\n"
          << "    specular = model != 0 ? min(mix(0.1, 1.0, mod(floor(clamp(specular, 0.0, 1.0) * bands), bands)"
          << " / (bands - 1.0)), diffuse) : 0.0;\n";
    out << "    float visible = " << shadow_code(light) << ";\n"
        << "    col += " << vec3_literal(light.color) << " * (albedo * diffuse * mix(" << literal(float(light.darkening))
        << ", 1.0, visible) + specular" << (light.specular_in_shadow ? "" : " * visible") << ");\n  }\n";
  }
  if (toon) out << "  if (dot(to_eye, n) < " << literal(float(e.silhouette)) << ") col = vec3(0.0);\n";
  out << "  return col;\n}\n";
  return out.str();
}

// A GLSL function of the material index m: `signature`'s value for each of the scene's materials, `otherwise` for
// any other m (-1: none); `first`, a statement before them.
template <class F>
std::string per_material(const Scene& s, const std::string& signature, F value, const std::string& otherwise,
                         const std::string& first = "") {
  std::ostringstream out;
  out << signature << " {\n" << first;
  for (size_t i = 0; i < s.materials.size(); ++i)
    out << "  if (m == " << i << ") return " << value(s.materials[i]) << ";\n";
  out << "  return " << otherwise << ";\n}\n";
  return out.str();
}

// The scene's materials by index: colour (its ramp colour, or its colour times its texture, looked up just below
// the surface as the seed does: p - n * SURF_DIST), specular model, strength and shininess.
std::string materials_code(const Scene& s) {
  const auto color = [&](const Material& m) {
    if (const auto ramped = ramp_color(s, m)) return vec3_literal(*ramped);
    const std::string scale = literal(float(m.texture_scale));
    std::string texture;
    if (m.texture == TextureMapping::planar) texture = " * mc_soil(q.x * " + scale + ", q.z * " + scale + ")";
    if (m.texture == TextureMapping::spherical) {
      const std::string r = "(q - " + vec3_literal(m.texture_origin) + ")";
      texture = " * mc_soil(fract(atan(length(" + r + ".xz), " + r + ".y) / 3.14159265) * " + scale + ", fract(atan(" +
                r + ".z, " + r + ".x) / 6.28318531) * " + scale + ")";
    }
    return vec3_literal(m.color) + texture;
  };
  const auto model = [](const Material& m) {
    return std::to_string(m.specular == SpecularModel::none ? 0 : m.specular == SpecularModel::phong ? 1 : 2);
  };
  const auto strength = [](const Material& m) { return literal(float(m.specular_strength)); };
  const auto shininess = [](const Material& m) { return literal(float(m.shininess)); };
  return per_material(s, "vec3 materialColor(int m, vec3 p, vec3 n)", color, "vec3(0.8)",
                      "  vec3 q = p - n * SURF_DIST;\n") +
         per_material(s, "int materialSpecular(int m)", model, "0") +
         per_material(s, "float materialStrength(int m)", strength, "0.0") +
         per_material(s, "float materialShininess(int m)", shininess, "1.0");
}

// Whether a material of the scene reflects or refracts secondary rays.
bool bounces(const Scene& s) {
  for (const Material& m : s.materials)
    if ((m.reflectivity > 0 || m.transparency > 0) && s.effects.max_bounces > 0) return true;
  return false;
}

// Mirror and refraction rays as march's Tracer follows them (reflect, refract through the solid marching the negated
// field, Schlick's Fresnel), to the scene's bounce depth. GLSL has no recursion: each depth is its own function,
// traceN marching and lighting a secondary ray, bounceN mixing in what the rays of depth N + 1 see.
std::string bounce_code(const Scene& s) {
  if (!bounces(s)) return "";
  const int depth = s.effects.max_bounces;
  std::ostringstream out;
  const auto reflectivity = [](const Material& m) { return literal(float(m.reflectivity)); };
  const auto transparency = [](const Material& m) { return literal(float(m.transparency)); };
  const auto ior = [](const Material& m) { return literal(float(m.ior)); };
  out << per_material(s, "float materialReflectivity(int m)", reflectivity, "0.0")
      << per_material(s, "float materialTransparency(int m)", transparency, "0.0")
      << per_material(s, "float materialIor(int m)", ior, "1.5")
      << "float schlick(float c, float n1, float n2) {\n  float r0 = (n1 - n2) / (n1 + n2), k = 1.0 - clamp(c, 0.0, 1.0);\n"
      << "  return r0 * r0 + (1.0 - r0 * r0) * k * k * k * k * k;\n}\n"
      << "// Into the solid at p and out again (bouncing inside at most 4 times): false when the ray stays in.\n"
      << "bool refractThrough(vec3 p, vec3 n, vec3 d, float ior, float t, out vec3 exitPoint, out vec3 exitDir) {\n"
      << "  vec3 dir = refract(d, n, 1.0 / ior);\n  if (dot(dir, dir) == 0.0) return false;\n"
      << "  float eps = hitEps(0.0) + 1e-6;\n  vec3 at = p - n * (2.0 * eps);\n"
      << "  for (int bounce = 0; bounce <= 4; ++bounce) {\n    March r = march(at, dir, MAX_DIST, -1.0);\n"
      << "    if (r.outcome != 0) return false;\n    vec3 exitAt = at + dir * r.t, nn = calcNormal(exitAt, t);\n"
      << "    vec3 refracted = refract(dir, -nn, ior);\n"
      << "    if (dot(refracted, refracted) > 0.0) {\n"
      << "      exitPoint = exitAt + nn * (2.0 * eps); exitDir = normalize(refracted); return true;\n    }\n"
      << "    dir = reflect(dir, -nn);\n    at = exitAt - nn * (2.0 * eps);\n  }\n  return false;\n}\n";
  for (int d = depth; d >= 0; --d) {
    const std::string next = std::to_string(d + 1);
    out << "vec3 bounce" << d << "(vec3 local, vec3 p, vec3 n, vec3 dir, int m, float t) {\n";
    if (d == depth)
      out << "  return local;\n}\n";
    else
      out << "  float reflectivity = materialReflectivity(m), transparency = materialTransparency(m);\n"
        << "  if (m < 0 || (reflectivity <= 0.0 && transparency <= 0.0)) return local;\n"
        << "  float offset = 2.0 * hitEps(t) + 1e-4;\n"
        << "  vec3 reflected = trace" << next << "(p + n * offset, reflect(dir, n));\n"
        << "  vec3 color = mix(local, reflected, reflectivity);\n"
        << "  if (transparency > 0.0) {\n    vec3 exitPoint, exitDir, refracted = " << vec3_literal(s.effects.background) << ";\n"
        << "    if (refractThrough(p, n, dir, materialIor(m), t, exitPoint, exitDir)) refracted = trace" << next
        << "(exitPoint, exitDir);\n"
        << "    float fresnel = schlick(-dot(dir, n), 1.0, materialIor(m));\n"
        << "    color = mix(color, fresnel * reflected + (1.0 - fresnel) * refracted, transparency);\n  }\n"
        << "  return color;\n}\n";
    if (d == 0) continue;
    // The ray of depth d: marched, its surface lit from its origin, its own bounces.
    out << "vec3 trace" << d << "(vec3 ro, vec3 rd) {\n  March r = march(ro, rd, MAX_DIST, 1.0);\n"
        << "  if (r.outcome != 0) return " << vec3_literal(s.effects.background) << ";\n"
        << "  vec3 p = ro + rd * r.t, n = calcNormal(p, r.t);\n  int m = int(map(p).y);\n"
        << "  return bounce" << d << "(shade(p, n, ro, m, r.t, 1.0), p, n, rd, m, r.t);\n}\n";
  }
  return out.str();
}

// mainImage: the camera's ray, the march (stopped at a nearer mesh), the surface lit, then the renderer's
// finish: glow on misses, step-count occlusion, no negative colour, fog; out by the scene's transfer (sRGB, or the
// values as they are), as marchcheck's PNGs.
std::string main_image_code(const Scene& s) {
  const Effects& e = s.effects;
  std::ostringstream out;
  out << "vec3 srgb(vec3 linear) {\n  vec3 c = clamp(linear, 0.0, 1.0);\n"
         "  return mix(1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, 12.92 * c, vec3(lessThanEqual(c, vec3(0.0031308))));\n}\n";
  out << "void mainImage(out vec4 fragColor, in vec2 fragCoord) {\n  vec3 ro, rd;\n  cameraRay(fragCoord, ro, rd);\n";
  if (s.meshes.empty())
    out << "  March r = march(ro, rd, MAX_DIST, 1.0);\n";
  else
    out << "  MeshHit mesh = meshHit(ro, rd, MAX_DIST);\n  March r = march(ro, rd, mesh.t, 1.0);\n";
  // The fogerty seed's reading (march::as_read): the distance alone, 0 past max_dist, shaded where t > 0.
  if (s.march.reading == RecordReading::seed_distance)
    out << "  if (r.outcome == 1) r.t = 0.0;\n  r.outcome = (r.outcome == 0 || r.outcome == 2) && r.t > 0.0 ? 0 : 1;\n";
  // The lee seed's (march::as_read): a miss at +inf, shaded anyway.
  if (s.march.reading == RecordReading::seed_infinity)
    out << "  if (r.outcome != 0) { r.outcome = 0; r.t = uintBitsToFloat(0x7f800000u); }\n";
  const bool meshes = !s.meshes.empty();
  out << "  vec3 col = " << vec3_literal(e.background) << ";\n"
      << "  bool onMesh = " << (meshes ? "mesh.hit && r.outcome != 0" : "false") << ";\n"
      << "  if (r.outcome == 0 || onMesh) {\n"
      << "    float t = " << (meshes ? "onMesh ? mesh.t : " : "") << "r.t;\n    vec3 p = ro + rd * t;\n"
      << "    vec3 n = " << (meshes ? "onMesh ? mesh.normal : " : "") << "calcNormal(p, t);\n"
      << "    int m = " << (meshes ? "onMesh ? mesh.material : " : "") << "int(map(p).y);\n"
      // The seed defect: the ray's direction taken for the eye's position.
      << "    col = shade(p, n, " << (e.eye_is_ray_direction ? "rd" : "ro") << ", m, t, "
      << (meshes ? "onMesh ? 1.0 : " : "") << "occlusion(p, n));\n";
  if (e.ao == AmbientOcclusion::steps)
    out << "    col -= vec3(float(r.steps) * float(r.steps) * " << literal(float(e.ao_steps_scale)) << ");\n";
  if (bounces(s)) out << "    col = bounce0(col, p, n, rd, m, t);\n";
  out << "    col = max(col, vec3(0.0));\n";
  if (e.fog > 0)
    out << "    col = mix(" << vec3_literal(e.fog_color) << ", col, exp(-" << literal(float(e.fog)) << " * t));\n";
  out << "  }";
  if (e.glow > 0)
    out << " else {\n    float g = clamp(1.0 - r.minAbsF / " << literal(float(e.glow_width)) << ", 0.0, 1.0);\n"
        << "    col += " << vec3_literal(e.glow_color) << " * (" << literal(float(e.glow)) << " * g * g);\n  }";
  out << "\n  fragColor = vec4(" << (s.output_transfer == OutputTransfer::srgb ? "srgb(col)" : "clamp(col, 0.0, 1.0)")
      << ", 1.0);\n}\n";
  return out.str();
}

}  // namespace

std::string shadertoy_shader(const Scene& scene) {
  const Scene& s = scene;
  for (const Material& m : s.materials)
    if (!m.texture_file.empty())
      throw SceneError("material '" + m.name + "': its texture_file is an image, which a self-contained shader "
                       "cannot carry (only the procedural soil is exported)");
  std::ostringstream out;
  out << "// " << s.name << ", exported by marchcheck (scenes --export-glsl): paste into Shadertoy as it is.\n"
      << "// The map is the scene's compiled field; the camera, marcher, normals, meshes, lights, shadows, textures,\n"
      << "// occlusion, reflections, refraction, glow and fog are the scene's, computed as marchcheck's renderer\n"
      << "// computes them, at the scene's time.\n";
  out << "#define MAX_STEPS " << s.march.max_steps << "\n#define MAX_DIST " << literal(float(std::min(s.march.max_dist, 1e30)))
      << "\n#define SURF_DIST " << literal(float(s.march.hit_eps)) << "\n";
  const std::string map = glsl_map(s.root, s.time, s.name);
  // Precision half: the field at mediump (binary16 on GPUs that honour it), the march and shading at highp.
  const bool half = s.march.precision == Precision::float16;
  out << (half ? "precision mediump float;\n" : "") << map << (half ? "precision highp float;\n" : "") << marcher_code(s);
  out << "float rayMarch(vec3 ro, vec3 rd) { return march(ro, rd, MAX_DIST, 1.0).t; }\n";
  bool textured = false;
  for (const Material& m : s.materials) textured = textured || m.texture != TextureMapping::none;
  if (textured) out << (map.find("float mc_lattice(") == std::string::npos ? kNoiseHelpers : "") << kSoilTexture;
  out << normal_code(s) << meshes_code(s) << shadow_functions(s) << occlusion_code(s) << materials_code(s)
      << lighting_code(s) << bounce_code(s) << camera_code(s) << main_image_code(s);
  return out.str();
}

}  // namespace marchcheck::sdf
