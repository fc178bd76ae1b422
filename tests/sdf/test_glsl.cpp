// GLSL fields: compiled by glslang, evaluated by the SPIR-V evaluator in float, double and Dual. The same
// operations in the same order as a built-in give its values bit for bit; bad sources are refused naming the
// file, the line and the problem; uniforms take the scene's values; a kind not declared is measured.
#include "batch_compare.hpp"

#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/half.hpp"
#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace marchcheck::sdf {
namespace {

// Declared exact: these tests are not about the measured constant.
Tape glsl_tape(const std::string& code, GlslSpec spec = {}) {
  Node n = make(Op::glsl);
  spec.code = code;
  spec.measured = false;
  spec.kind = Kind::exact;
  n.glsl = std::make_shared<const GlslField>(spec, code, "test.glsl");
  return compile(n);
}

// Points where the two tapes' float or double values differ in any bit, of 500 in [-2, 2]^3.
int differing(const Tape& a, const Tape& b) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-2, 2);
  int bad = 0;
  for (int i = 0; i < 500; ++i) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    bad += !testing::same_bits(evaluate(a, p), evaluate(b, p)) ||
           !testing::same_bits(evaluate(a, glm::vec3(p)), evaluate(b, glm::vec3(p)));
  }
  return bad;
}

// iq's formulas, as Shadertoy code writes them; the tape's kernels run the same operations in the same order
// (the float constants are the same floats), so any difference is an evaluator's.
TEST(Glsl, SphereBoxAndTorusGiveTheBuiltinsValuesBitForBit) {
  EXPECT_EQ(differing(glsl_tape("float map(vec3 p) { return length(p) - 0.75; }"), compile(sphere(0.75))), 0);
  EXPECT_EQ(differing(glsl_tape("float map(vec3 p) { vec3 q = abs(p) - vec3(0.5, 0.25, 0.75);\n"
                                "  return length(max(q, 0.0)) + min(max(q.x, max(q.y, q.z)), 0.0); }"),
                      compile(box({0.5, 0.25, 0.75}))),
            0);
  EXPECT_EQ(differing(glsl_tape("float map(vec3 p) { vec2 q = vec2(length(p.xz) - 1.0, p.y);\n"
                                "  return length(q) - 0.25; }"),
                      compile(torus(1, 0.25))),
            0);
}

// GLSL's built-ins and constructs as the GLSL specification defines them, at p = (-0.25, 0.5, 2): each expression
// against its value worked by hand (exact in double but for the transcendental ones, which are libm's: 1e-15).
TEST(Glsl, BuiltinsAndConstructsFollowTheGlslSpecification) {
  struct Case {
    const char* body;  // of map(vec3 p)
    double expected;
  };
  const Case cases[] = {
      {"return mod(p.x, 1.0);", 0.75},  // x - y floor(x / y), not C's fmod (-0.25)
      {"return fract(p.x);", 0.75},
      {"return sign(p.x);", -1},
      {"return clamp(p.z, 0.0, 1.0);", 1},
      {"return mix(p.x, p.z, 0.25);", 0.3125},  // x (1 - a) + y a
      {"return smoothstep(0.0, 1.0, p.y);", 0.5},
      {"return step(0.0, p.x) + 2.0 * step(p.x, 0.0);", 2},
      {"return atan(p.y, p.z);", std::atan2(0.5, 2.0)},
      {"return length(p);", std::sqrt(0.0625 + 0.25 + 4)},
      {"return normalize(p).z;", 2 / std::sqrt(0.0625 + 0.25 + 4)},
      {"return reflect(vec3(1.0, -1.0, 0.0), vec3(0.0, 1.0, 0.0)).y;", 1},
      {"return cross(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0)).z;", 1},
      {"return (mat2(1.0, 2.0, 3.0, 4.0) * vec2(1.0, p.y)).y;", 4},   // column-major: 2 + 4 p.y
      {"return (vec2(1.0, p.y) * mat2(1.0, 2.0, 3.0, 4.0)).y;", 5},   // row vector: 3 + 4 p.y
      {"return (mat2(1.0, 2.0, 3.0, 4.0) * mat2(p.y))[1].y;", 2},  // 0.5 times column 1, (3, 4)
      {"return pow(2.0, 3.0) + exp2(p.z) + log2(8.0) + inversesqrt(4.0);", 8 + 4 + 3 + 0.5},
      {"return max(p.x, p.y) + 10.0 * min(p.x, p.y);", 0.5 - 2.5},
      {"return float(7 / int(p.z)) + 10.0 * float(-7 / int(p.z));", 3 - 30},  // truncation toward zero
      {"return float(7 % int(p.z + 1.0)) + float(uint(7) >> 1u);", 1 + 3},
      {"return float(floatBitsToUint(p.y) >> 23);", 126},  // 0.5's exponent field
      // int <-> uint: the same bits (broken variant: glsl-integer-bitcast-as-float)
      {"return float(uint(7 % int(p.z + 2.0))) + float(int(0xfffffffeu));", 3 - 2},
      {"float a[3] = float[3](1.0, 2.0, 3.0); return a[int(p.z)];", 3},
      {"switch (int(p.z)) { case 1: return 4.0; case 2: return 5.0; default: return 1.0; }", 5},
      {"return any(greaterThan(p, vec3(1.0))) && !all(lessThan(p, vec3(1.0))) ? 1.0 : 0.0;", 1},
      {"float s = 0.0; int i = 0; do { s += p.y; ++i; } while (i < 4); return s;", 2},
      {"vec4 v = vec4(p, 1.0); v.yw *= 2.0; v.x -= v.w; return v.x + 10.0 * v.y;", -2.25 + 10},
  };
  for (const Case& c : cases) {
    const Tape t = glsl_tape(std::string("float map(vec3 p) { ") + c.body + " }");
    EXPECT_NEAR(evaluate(t, glm::dvec3(-0.25, 0.5, 2)), c.expected, 1e-15) << c.body;
  }
}

// Binary16 as IEEE rounds it: to nearest, ties to even (2049 and 2051 lie halfway between neighbours 2 apart),
// overflow past 65504 to infinity, underflow below half the smallest subnormal (2^-24) to zero. Broken variants:
// no rounding at all (glsl-half-unrounded), ties away from zero (sdf-half-ties-up).
TEST(Glsl, HalfRoundsAsIeeeBinary16) {
  EXPECT_EQ(float(Half(2049.0)), 2048.0f);
  EXPECT_EQ(float(Half(2051.0)), 2052.0f);
  EXPECT_EQ(float(Half(1.0) + Half(0x1p-11)), 1.0f);  // the tie goes to 1's even significand
  EXPECT_EQ(float(Half(1.0) + Half(0x1p-10)), 1.0f + 0x1p-10f);
  EXPECT_EQ(float(Half(0.1)), 0.0999755859375f);
  EXPECT_EQ(float(Half(65504.0) + Half(15.0)), 65504.0f);   // below the midpoint 65520
  EXPECT_TRUE(std::isinf(float(Half(65504.0) + Half(16.0))));  // at it: ties to even, past the largest
  EXPECT_TRUE(std::isinf(float(Half(-1e30))) && float(Half(-1e30)) < 0);
  EXPECT_TRUE(std::isnan(float(Half(std::nan("")))));
  EXPECT_EQ(float(Half(0x1p-24) * Half(0.25)), 0.0f);
  EXPECT_EQ(float(Half(3.0) / 7), float(Half(3.0f / 7.0f)));  // a number operand rounded first, then the quotient
}

// round_to_half against GCC's own conversion to _Float16, for floats and doubles of every binade binary16 spans
// (subnormals included) and the ties between neighbours (x.5 ulp, both parities), on both signs. Broken variant:
// ties away from zero (sdf-half-ties-up).
TEST(Glsl, HalfRoundingIsGccsFloat16Conversion) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> significand(1, 2);
  int compared = 0;
  for (int binade = -26; binade <= 15; ++binade)
    for (int i = 0; i < 2000; ++i) {
      const double ulp = std::ldexp(1.0, std::max(binade, -14) - 10);
      double x = std::ldexp(significand(rng), binade);
      if (i % 4 == 0) x = (std::floor(x / ulp) + 0.5) * ulp;  // a tie
      if (i % 2) x = -x;
      if (!(std::abs(x) < 65520)) continue;
      const float f = static_cast<float>(x);
      EXPECT_EQ(round_to_half(f), static_cast<float>(static_cast<_Float16>(f))) << f;
      EXPECT_EQ(round_to_half(x), static_cast<float>(static_cast<_Float16>(x))) << x;
      ++compared;
    }
  EXPECT_GT(compared, 80000);
}

// A GLSL field with precision half computes every operation in binary16: length(p) - 1 at p worked by hand, each
// step rounded (r). The same field in float differs. Broken variant: the half flag ignored (glsl-half-ignored).
TEST(Glsl, AHalfFieldRoundsEveryOperation) {
  const auto r = [](double x) { return static_cast<double>(static_cast<float>(static_cast<_Float16>(x))); };
  const double x = r(0.3), y = r(0.4), z = r(1.2);
  const double want = r(r(std::sqrt(r(r(r(x * x) + r(y * y)) + r(z * z)))) - 1);
  GlslSpec spec;
  spec.measured = false;
  spec.half = true;
  const GlslField half(spec, "float map(vec3 p) { return length(p) - 1.0; }", "half.glsl");
  EXPECT_EQ(half.distance(glm::vec3(0.3f, 0.4f, 1.2f)), static_cast<float>(want));
  EXPECT_NE(half.with_half(false).distance(glm::vec3(0.3f, 0.4f, 1.2f)), static_cast<float>(want));
  EXPECT_EQ(half.distance(glm::dvec3(0.3, 0.4, 1.2)), std::sqrt(0.09 + 0.16 + 1.44) - 1);  // double stays double
}

// A built-in tree in half (a scene's precision "half") is the same binary16 arithmetic as the same field written in
// GLSL at mediump: a translated sphere, bit for bit at points around its surface, where rounding decides the
// sign. Broken variants: the tape's half flag ignored (sdf-half-tape-in-float), the point not rounded to binary16
// before the tape runs (sdf-half-point-unrounded).
TEST(Glsl, ABuiltinTreeInHalfIsTheGlslFieldAtMediump) {
  GlslSpec spec;
  spec.measured = false;
  spec.half = true;
  const GlslField glsl(spec, "float map(vec3 p) { return length(p - vec3(0.5, -1.0, 2.0)) - 3.0; }", "half.glsl");
  Tape tape = compile(translate({0.5, -1, 2}, sphere(3)));
  tape.half = true;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int differ = 0, unlike_float = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const glm::vec3 p(glm::dvec3(0.5, -1, 2) + d * (3 + 0.01 * u(rng)));
    differ += evaluate(tape, p) != glsl.distance(p);
    unlike_float += evaluate(tape, p) != glsl.with_half(false).distance(p);
  }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(unlike_float, 1000);
}

// The comparison can fail: the sphere 1 float ulp larger (0.75 + 2^-24 is representable) is caught nearly
// everywhere.
TEST(Glsl, AFieldOneUlpApartIsCaught) {
  EXPECT_GT(differing(glsl_tape("float map(vec3 p) { return length(p) - 0.75000006; }"), compile(sphere(0.75))),
            400);
}

// A vec2 result's .x is the distance; Dual gradients flow through helpers, loops and matrices.
TEST(Glsl, GradientsFlowThroughHelpersLoopsAndMatrices) {
  const Tape t = glsl_tape(
      "vec2 rot(vec2 v, float a) { return mat2(cos(a), sin(a), -sin(a), cos(a)) * v; }\n"
      "vec2 map(vec3 p) { for (int i = 0; i < 3; ++i) p.xz = rot(p.xz, 0.3); return vec2(length(p) - 1.0, 7.0); }");
  using D = Dual<double>;
  const glm::dvec3 p(0.3, 0.4, 1.2);
  const D f = evaluate(t, glm::vec<3, D>(D(p.x, {1, 0, 0}), D(p.y, {0, 1, 0}), D(p.z, {0, 0, 1})));
  // A rotated sphere is the sphere: f = |p| - 1, gradient p / |p|. Rounding through three rotations: 1e-15.
  EXPECT_NEAR(f.v, glm::length(p) - 1, 1e-14);
  EXPECT_NEAR(glm::length(f.d - p / glm::length(p)), 0, 1e-14);
}

std::string error_of(const std::string& code, const std::string& function = "map") {
  try {
    GlslSpec spec;
    spec.function = function;
    GlslField f(spec, code, "user/field.glsl");
  } catch (const GlslError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Glsl, BadSourcesNameTheFileTheLineAndTheProblem) {
  EXPECT_EQ(error_of("float map(vec3 p) {\n  return lenght(p) - 1.0;\n}"),
            "user/field.glsl:2: 'lenght' : no matching overloaded function found ");
  EXPECT_NE(error_of("float sdf(vec3 p) { return length(p) - 1.0; }").find(
                "user/field.glsl: no function map(vec3) returning float, vec2, vec3 or vec4"),
            std::string::npos);
  EXPECT_EQ(error_of("float sdf(vec3 p) { return length(p) - 1.0; }", "sdf"), "(no error)");
  EXPECT_NE(error_of("uniform sampler2D iChannel0;\n"
                     "float map(vec3 p) { return texture(iChannel0, p.xy).x; }")
                .find("textures"),
            std::string::npos);
}

TEST(Glsl, AScenesGlslNodeNamesItsPlaceWhenItsCodeIsBad) {
  try {
    scene_from_json(R"({"sdf": {"type": "glsl", "code": "float map(vec3 p) { return q; }"}})", "s.json");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "s.json: /sdf: /sdf/code:1: 'q' : undeclared identifier ");
  }
  try {
    scene_from_json(R"({"sdf": {"type": "glsl", "source": "missing.glsl"}})", "dir/s.json");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/sdf/source: cannot read"), std::string::npos) << e.what();
  }
}

// Whole shaders pasted as they are: a Shadertoy one (mainImage, its own marcher, a texture read in shading, the
// iChannel and iResolution inputs) and a WebGL one (#version 300 es, precision, its own main, in/out variables,
// its own uniform iTime). Their map imports; only reading a texture in the field itself is refused.
TEST(Glsl, WholePastedShadersImportTheirMap) {
  const std::string shadertoy =
      "float map(vec3 p) { return length(p) - 1.0; }\n"
      "void mainImage(out vec4 fragColor, in vec2 fragCoord) {\n"
      "  vec2 uv = (fragCoord - 0.5 * iResolution.xy) / iResolution.y;\n"
      "  vec3 ro = vec3(0, 0, -3), rd = normalize(vec3(uv, 1));\n"
      "  float t = 0.0;\n"
      "  for (int i = 0; i < 64; i++) { float d = map(ro + rd * t); if (d < 1e-3) break; t += d; }\n"
      "  fragColor = texture(iChannel0, uv) * exp(-t) + vec4(iChannelResolution[0], iTimeDelta);\n"
      "}\n";
  EXPECT_EQ(evaluate(glsl_tape(shadertoy), glm::dvec3(2, 0, 0)), 1.0);
  const std::string webgl =
      "#version 300 es\nprecision highp float;\nuniform float iTime;\nin vec2 vUv;\nout vec4 fragColor;\n"
      "float map(vec3 p) { return length(p) - 1.0 - iTime; }\n"
      "void main() { fragColor = vec4(map(vec3(vUv, 0.0))); }\n";
  EXPECT_EQ(evaluate(glsl_tape(webgl), glm::dvec3(2, 0, 0)), 1.0);
  EXPECT_NE(error_of("float map(vec3 p) { return length(p) - texture(iChannel0, p.xy).x; }").find(
                "textures, samplers and buffers are not supported in a field (iChannel0)"),
            std::string::npos);
}

// A vec2 result's .y selects the scene's materials by the node's list: 0 the first, 1 the second; any other .y keeps
// the node's own, in the one-point and the batched tape alike, and the scene file round-trips the list. Broken
// variant: .y ignored (glsl-material-ignored).
TEST(Glsl, AResultsYSelectsTheNodesMaterials) {
  const std::string text = R"({"materials": [{"name": "own"}, {"name": "red"}, {"name": "blue"}],
    "sdf": {"type": "glsl", "kind": "exact", "material": "own", "materials": ["red", "blue"],
            "code": "vec2 map(vec3 p) { return vec2(length(p) - 1.0, p.x < 0.0 ? 0.0 : (p.x < 2.0 ? 1.0 : 7.0)); }"}})";
  for (const Scene& scene : {scene_from_json(text, "m.json"), scene_from_json(scene_to_json(scene_from_json(text, "m.json")), "m.json")}) {
    const Tape tape = compile(scene.root);
    const glm::vec3 at[] = {{-1, 0, 0}, {1, 0, 0}, {3, 0, 0}};
    const int want[] = {1, 2, 0};  // red, blue, and the node's own for .y = 7
    float xs[3], ys[3], zs[3], values[3];
    int batched[3];
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(sample(tape, at[i]).material, want[i]) << i;
      xs[i] = at[i].x, ys[i] = at[i].y, zs[i] = at[i].z;
    }
    sample_batch(tape, xs, ys, zs, values, batched, 3);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(batched[i], want[i]) << i;
  }
  std::string unknown = text;
  unknown.replace(unknown.find("\"blue\"]"), 6, "\"green\"");
  try {
    scene_from_json(unknown, "m.json");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "m.json: /sdf/materials/1: expected the name of one of the scene's materials");
  }
}

// A GLSL file alone colours its material ids: .y = 0 to 7 picks the scene's materials y0 to y7; a float result, or
// a .y past them, keeps no material (the renderer's grey). Broken variant: no materials made
// (sdf-glsl-file-no-materials).
TEST(Glsl, AFileAlonePicksMaterialsByItsY) {
  const Scene ids = glsl_scene("ids.glsl", {}, "vec2 map(vec3 p) { return vec2(length(p) - 1.0, p.x < 0.0 ? 1.0 : 9.0); }");
  const Tape tape = compile(ids.root);
  ASSERT_EQ(ids.materials.size(), 8u);
  EXPECT_EQ(ids.materials[static_cast<size_t>(sample(tape, glm::vec3(-1, 0, 0)).material)].name, "y1");
  EXPECT_EQ(sample(tape, glm::vec3(1, 0, 0)).material, -1);
  const Scene plain = glsl_scene("plain.glsl", {}, "float map(vec3 p) { return length(p) - 1.0; }");
  EXPECT_EQ(sample(compile(plain.root), glm::vec3(-1, 0, 0)).material, -1);
}

// Without a loader (the scene fuzzer's case) nothing external runs: no file read, no GLSL compiled.
TEST(Glsl, WithoutALoaderAGlslNodeIsRefused) {
  try {
    scene_from_json(R"({"sdf": {"type": "glsl", "code": "float map(vec3 p) { return length(p) - 1.0; }"}})", "s.json",
                    {});
    FAIL() << "compiled";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "s.json: /sdf: a GLSL field is not compiled here (no loader: meshes and GLSL are off)");
  }
}

// A loop that never ends on the CPU is stopped by the bound on work: the field is NaN there, not a hang; where it
// does not end at the origin the source is refused. (In float d stops growing at 2^24 and the loop never ends.)
TEST(Glsl, ALoopThatDoesNotEndGivesNaNOrIsRefused) {
  const Tape t = glsl_tape("float map(vec3 p) { float d = 1.0; while (p.x > 1.0 && d > 0.0) d += 1.0; return d; }");
  EXPECT_TRUE(std::isnan(evaluate(t, glm::dvec3(2, 0, 0))));
  EXPECT_EQ(evaluate(t, glm::dvec3(0)), 1.0);
  EXPECT_NE(error_of("float map(vec3 p) { float d = 1.0; while (d > 0.0) d += 1.0; return d; }")
                .find("does not finish within 1000000 SPIR-V instructions at (0, 0, 0)"),
            std::string::npos);
}

TEST(Glsl, UniformsTakeTheScenesValuesAndOthersAreZero) {
  const std::string code = "uniform vec3 offset;\nfloat map(vec3 p) { return length(p - offset) - 1.0 + iTime; }";
  EXPECT_EQ(evaluate(glsl_tape(code), glm::dvec3(0)), -1.0);  // |0 - 0| - 1 + 0
  GlslSpec spec;
  spec.uniforms = {{"offset", {1, 0, 0}}, {"iTime", {0.5}}};
  EXPECT_EQ(evaluate(glsl_tape(code, spec), glm::dvec3(0)), 0.5);  // |0 - (1, 0, 0)| - 1 + 0.5
  spec.uniforms = {{"offset", {1, 0}}};
  EXPECT_THROW(glsl_tape(code, spec), GlslError) << "two values for a vec3";
}

// Not declared, the kind is Lipschitz with the measured slope: 3 for a sphere's distance times 3, less by the
// angle between the steepest of 20000 random pair directions and the gradient (about 0.01 rad: 1 - 5e-5).
TEST(Glsl, AKindNotDeclaredIsMeasured) {
  Node n = make(Op::glsl);
  n.glsl = std::make_shared<const GlslField>(GlslSpec{}, "float map(vec3 p) { return (length(p) - 1.0) * 3.0; }",
                                             "t.glsl");
  const FieldInfo info = derive_info(n);
  EXPECT_EQ(info.kind, Kind::lipschitz);
  EXPECT_NEAR(info.lipschitz, 3.0, 3e-4);
  EXPECT_NE(info.reason.find("measured"), std::string::npos);
}

// What the GL driver's run and the sweep rely on: glslang's view of a source's uniforms and of where its map's
// body begins. Broken variants: a const or a #define taken for a uniform; the counter put before the body.
TEST(Glsl, UniformsAreFoundAndAStatementGoesFirstInTheBody) {
  const std::string code = "#define K 2.0\nconst float C = 1.0;\nuniform vec3 offset;\n"
                           "float map(vec3 p)\n  /* the body */ {\n  return length(p + offset) - C * K + iTime;\n}\n";
  EXPECT_TRUE(glsl_declares_uniform(code, "u.glsl", "offset"));
  EXPECT_TRUE(glsl_declares_uniform(code, "u.glsl", "iTime")) << "Shadertoy's inputs are declared for the source";
  EXPECT_FALSE(glsl_declares_uniform(code, "u.glsl", "C"));
  EXPECT_FALSE(glsl_declares_uniform(code, "u.glsl", "K"));
  const std::string counted = run_first_in(code, "u.glsl", "map", "k++;");
  EXPECT_NE(counted.find("/* the body */ { k++; \n  return"), std::string::npos) << counted;
  EXPECT_EQ(std::count(counted.begin(), counted.end(), '\n'), std::count(code.begin(), code.end(), '\n'))
      << "lines keep their numbers";
  EXPECT_THROW(run_first_in(code, "u.glsl", "sdf", "k++;"), GlslError);
}

// A shader's own limits, read as its marcher sees them: a #define, a const global, or none. Broken variant: a
// name the source lacks read as 0 would set a step limit of 0.
TEST(Glsl, ConstantsOfTheSourceAreRead) {
  const std::string code = "#define MAX_STEPS 64\nconst float FAR = 20.0;\nfloat map(vec3 p) { return p.x; }\n";
  EXPECT_EQ(glsl_constant(code, "c.glsl", "MAX_STEPS"), 64.0);
  EXPECT_EQ(glsl_constant(code, "c.glsl", "FAR"), 20.0);
  EXPECT_EQ(glsl_constant(code, "c.glsl", "SURF_DIST"), std::nullopt);
}

}  // namespace
}  // namespace marchcheck::sdf
