// Scenes exported as GLSL and imported back: marchcheck's GLSL evaluator gives the exported map the tape's float
// values bit for bit, because every GLSL kernel mirrors its C++ kernel operation for operation (smath's min, max,
// clamp, mix, round and the sequential dot, not GLSL's built-ins, whose NaN, signed-zero and rounding behaviour
// differ). Broken variant: a kernel with one operation reordered differs by an ulp somewhere among the points.
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/glsl_export.hpp"
#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace marchcheck::sdf {
namespace {

// The points each comparison runs at: a box around the scene's camera target, and near the origin.
std::vector<glm::vec3> points_around(glm::dvec3 centre, double half, int n) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-half, half);
  std::vector<glm::vec3> out;
  for (int i = 0; i < n; ++i) out.push_back(glm::vec3(centre + glm::dvec3(u(rng), u(rng), u(rng))));
  return out;
}

bool same_float(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0 || (a != a && b != b); }

// The exported map at each point against the tape, bit for bit (half: both in binary16, GLSL's mediump); the first
// point that differs.
std::string first_difference(const Node& root, double time, const std::string& name, const std::vector<glm::vec3>& at,
                             bool half = false) {
  Tape tape = compile(root, time);
  tape.half = half;
  GlslSpec spec;
  spec.measured = false;
  spec.half = half;
  const GlslField imported(spec, glsl_map(root, time, name), name + ".glsl");
  for (const glm::vec3 p : at) {
    const float want = evaluate(tape, p), got = imported.distance(p);
    if (!same_float(want, got))
      return "at (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + "): tape " +
             std::to_string(want) + ", exported " + std::to_string(got);
  }
  return "";
}

TEST(GlslExport, EveryOperatorsExampleRoundTripsBitForBit) {
  int exported = 0;
  for (const Op op : all_ops()) {
    // 2D shapes are exported extruded, as every-operator tests examine them.
    const Node node = op_info(op).dimension == 2 ? make(Op::extrude, {{"half_depth", {0.3}}}, {example(op)}) : example(op);
    try {
      const std::string diff = first_difference(node, 0, "example", points_around(glm::dvec3(0), 2.5, 400));
      EXPECT_EQ(diff, "") << op_info(op).name;
      ++exported;
    } catch (const SceneError& e) {
      // Only what has no GLSL form is refused, saying why.
      EXPECT_EQ(op, Op::glsl) << op_info(op).name << ": " << e.what();
    }
  }
  EXPECT_GE(exported, 30);
}

// The noise hash's 64-bit lattice coordinates in 32-bit halves: negative cells (two's complement), cells past
// 2^32 and past int64's folding bound (4e18: cell 0), where the halves carry and borrow. Broken variants:
// sdf-export-noise-carry-dropped, -negative-cells, -product-carry, -truncated.
TEST(GlslExport, TheHeightfieldsHashAgreesAtEveryMagnitude) {
  const Node field = make(Op::heightfield, {{"octaves", {0.5, 1, 0.25, 3.5}}}, {});
  std::vector<glm::vec3> at;
  std::mt19937 rng(5);
  for (const double magnitude : {0.5, 3.0, 7e4, 3e9, 5e12, 2e17, 3.9e18, 5e18, 1e25})
    for (int i = 0; i < 40; ++i) {
      std::uniform_real_distribution<double> u(-magnitude, magnitude);
      at.emplace_back(u(rng), 0.3f, u(rng));
    }
  EXPECT_EQ(first_difference(field, 0, "heightfield", at), "");
  // The seed's sin hash, in float as its shader computes it, where float cells are whole numbers.
  const Node seed = make(Op::heightfield, {{"hash", {1}}, {"octaves", {0.5, 1, 0.25, 3.5}}}, {});
  std::vector<glm::vec3> near(at.begin(), at.begin() + 120);  // magnitudes 0.5 to 7e4
  EXPECT_EQ(first_difference(seed, 0, "heightfield", near), "");
}

// Every built-in, mesh-icosphere's 5120 triangles included: its packed mesh walk finds the same nearest triangle
// and sign. Broken variants: boxes rounded inwards (sdf-export-mesh-box-inwards), boxes skipped while nearer than
// the best (sdf-export-mesh-prune-early), inside on any crossing (sdf-export-mesh-parity-any), the face normal's
// sign everywhere (sdf-export-mesh-sign-from-face).
TEST(GlslExport, EveryBuiltinRoundTripsBitForBit) {
  int exported = 0;
  for (const std::string& name : builtin_scene_names()) {
    const Scene scene = builtin_scene(name);
    const bool half = scene.march.precision == Precision::float16;
    EXPECT_EQ(first_difference(scene.root, scene.time, name, points_around(scene.camera.target, 3, 300), half), "")
        << name;
    ++exported;
  }
  EXPECT_EQ(exported, 32);
}

// A scene in half exports its field under mediump and the rest at highp, as the seed fogerty declares it: the march
// and shading stay float's, as marchcheck's renderer keeps them. Broken variant: no precision statement
// (sdf-export-mediump-dropped).
TEST(GlslExport, AHalfScenesFieldIsExportedAtMediump) {
  const std::string shader = shadertoy_shader(builtin_scene("fogerty-defect-mediump"));
  const size_t mediump = shader.find("precision mediump float;\n"), map = shader.find("vec2 map(vec3 p)"),
               highp = shader.find("precision highp float;\n"), march = shader.find("march(vec3");
  ASSERT_NE(mediump, std::string::npos);
  ASSERT_NE(highp, std::string::npos);
  EXPECT_LT(mediump, map);
  EXPECT_LT(map, highp);
  EXPECT_LT(highp, march);
  EXPECT_EQ(shadertoy_shader(builtin_scene("fogerty")).find("precision mediump"), std::string::npos);
}

// What the exported marcher leaves out is said in it: clipping to the bounds and the perturbed step bound, each
// only where the scene asks for it. Broken variant: the perturbed bound left out silently
// (sdf-export-perturbed-unsaid).
TEST(GlslExport, TheMarcherSaysWhichSettingsItDoesNotExport) {
  Scene scene = builtin_scene("crum-lattice");
  const std::string plain = shadertoy_shader(scene);
  EXPECT_EQ(plain.find("is not exported"), std::string::npos);
  apply_setting(scene, "clip", "bounds");
  apply_setting(scene, "step_bound", "perturbed");
  const std::string asked = shadertoy_shader(scene);
  EXPECT_NE(asked.find("// clip=bounds is not exported"), std::string::npos);
  EXPECT_NE(asked.find("// step_bound=perturbed is not exported"), std::string::npos);
}

// Beside a regular tetrahedron's edges (70.5 degrees inside) a point's closest triangle can face away from it: the
// export's sign there is the ray's, not that face's. Broken variant: the face normal's sign everywhere
// (sdf-export-mesh-sign-from-face).
TEST(GlslExport, AMeshsSignIsRightBesideEdgesSharperThanARightAngle) {
  Scene scene;
  scene.root = mesh("tetrahedron");
  load_meshes(scene, [](const std::string&) {
    return meshes::Mesh{{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}}, {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}}};
  });
  EXPECT_EQ(first_difference(scene.root, 0, "tetrahedron", points_around(glm::dvec3(0), 2, 400)), "");
}

// A mesh past the constant space a GL driver holds is refused, saying what it needs: icosphere(1, 5)'s 10242
// vertices take 3 x 10242 / 4 = 7682 slots, its 3 x 20480 indices of 14 bits 6720, its 3414 boxes of 6 bytes 1281.
// Broken variant: only the vertices counted (sdf-export-mesh-slots-words-uncounted).
TEST(GlslExport, AMeshPastTheDriversConstantSpaceIsRefusedSayingWhatItNeeds) {
  Scene scene;
  scene.root = mesh("procedural:icosphere(1,5)");
  load_meshes(scene);
  try {
    glsl_map(scene.root, 0, "big");
    FAIL() << "exported";
  } catch (const SceneError& e) {
    const std::string why = e.what();
    EXPECT_NE(why.find("cannot export big as GLSL: its mesh of 20480 triangles needs 15683 constant slots"), std::string::npos) << why;
    EXPECT_NE(why.find("more than the 3840 a GL driver holds"), std::string::npos) << why;
  }
}

}  // namespace
}  // namespace marchcheck::sdf
