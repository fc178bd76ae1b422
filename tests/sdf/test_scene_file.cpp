// Scene files: every built-in round-trips bit for bit; bad files name the place and the problem.
#include "marchcheck/meshes/io.hpp"
#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/mesh_distance.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace marchcheck::sdf {
namespace {

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

class BuiltinRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinRoundTrip, ExportThenLoadGivesTheSameSceneBitForBit) {
  const Scene original = builtin_scene(GetParam());
  const std::string text = scene_to_json(original);
  const Scene loaded = scene_from_json(text, GetParam() + ".json");
  EXPECT_EQ(scene_to_json(loaded), text);
  const Tape a = compile(original.root, original.time), b = compile(loaded.root, loaded.time);
  EXPECT_TRUE(same_bits(a.constants, b.constants));
  ASSERT_EQ(a.code.size(), b.code.size());
  for (size_t i = 0; i < a.code.size(); ++i) {
    EXPECT_EQ(a.code[i].op, b.code[i].op);
    EXPECT_EQ(a.code[i].arg, b.code[i].arg);
    EXPECT_EQ(a.code[i].material, b.code[i].material);
  }
  // Shortest round-trip number printing: equal text means equal doubles for every setting.
  EXPECT_EQ(original.time, loaded.time);
  EXPECT_EQ(original.lights.size(), loaded.lights.size());
}

INSTANTIATE_TEST_SUITE_P(All, BuiltinRoundTrip, ::testing::ValuesIn(builtin_scene_names()), [](const auto& param_info) {
  std::string name = param_info.param;
  for (auto& c : name)
    if (c == '-') c = '_';
  return name;
});

std::string error_of(const std::string& text) {
  try {
    scene_from_json(text, "bad.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

// A ramp colour lies between the two ramp colours its value falls between: 0.75 of a three-colour ramp is half way
// from the second to the third; 1 is the last; no ramp value, or no ramp, is none. Broken variant: every value
// mixed from the first colour (sdf-ramp-colour-first).
TEST(SceneFile, ARampColourMixesTheTwoColoursItsValueFallsBetween) {
  Scene s;
  s.effects.ramp = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Material m;
  m.ramp_value = 0.75;
  EXPECT_EQ(ramp_color(s, m), glm::dvec3(0, 0.5, 0.5));
  m.ramp_value = 1;
  EXPECT_EQ(ramp_color(s, m), glm::dvec3(0, 0, 1));
  m.ramp_value = -1;
  EXPECT_FALSE(ramp_color(s, m).has_value());
  m.ramp_value = 0.5;
  s.effects.ramp.clear();
  EXPECT_FALSE(ramp_color(s, m).has_value());
}

// Each effect a scene can switch on is declared by its name, however little of it there is. Broken variants:
// light fog left out; a lens with k2 alone not declared as distorting.
TEST(SceneFile, DeclaredEffectsNameEveryEffectSwitchedOn) {
  const auto declares = [](const Scene& s, const std::string& effect) {
    const auto effects = declared_effects(s);
    return std::find(effects.begin(), effects.end(), effect) != effects.end();
  };
  Scene s = builtin_scene("lee-flat");
  EXPECT_FALSE(declares(s, "fog"));
  s.effects.fog = 0.05;
  EXPECT_TRUE(declares(s, "fog"));
  s.camera.model = CameraModel::intrinsics;
  s.camera.k1 = s.camera.k2 = s.camera.p1 = s.camera.p2 = 0;  // lee's lens has k1
  EXPECT_FALSE(declares(s, "lens-distortion"));
  for (double CameraSpec::*term : {&CameraSpec::k1, &CameraSpec::k2, &CameraSpec::p1, &CameraSpec::p2}) {
    Scene lens = s;
    lens.camera.*term = 0.01;
    EXPECT_TRUE(declares(lens, "lens-distortion"));
  }
}

// A smaller render of the same view: the image and every intrinsic in pixels scale by the width's ratio.
// Broken variant: cx scaled twice and cy left where it was.
TEST(SceneFile, ScaledToWidthScalesTheIntrinsicsWithTheImage) {
  Scene s = builtin_scene("lee-flat");
  s.width = 640;
  s.height = 360;
  s.camera.model = CameraModel::intrinsics;
  s.camera.fx = 600;
  s.camera.fy = 580;
  s.camera.cx = 300;
  s.camera.cy = 200;
  const Scene half = scaled_to_width(s, 320);
  EXPECT_EQ(half.width, 320);
  EXPECT_EQ(half.height, 180);
  EXPECT_EQ(half.camera.fx, 300);
  EXPECT_EQ(half.camera.fy, 290);
  EXPECT_EQ(half.camera.cx, 150);
  EXPECT_EQ(half.camera.cy, 100);
  s.camera.cx = s.camera.cy = -1;  // the image centre, whatever the size
  EXPECT_EQ(scaled_to_width(s, 320).camera.cx, -1);
  EXPECT_EQ(scaled_to_width(s, 320).camera.cy, -1);
}

// The march's coordinates: a setting and a scene-file key like the others, kept by a round trip and refused with
// the names it takes. Broken variant: the key's names swapped (sdf-coordinates-names-swapped).
TEST(SceneFile, CoordinatesAreAKeyWorldOrCamera) {
  Scene s = builtin_scene("crum-smooth");
  EXPECT_EQ(s.march.coordinates, Coordinates::world);
  apply_setting(s, "coordinates", "camera");
  EXPECT_EQ(s.march.coordinates, Coordinates::camera);
  EXPECT_EQ(scene_from_json(scene_to_json(s), "s.json").march.coordinates, Coordinates::camera);
  try {
    apply_setting(s, "coordinates", "eye");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("'eye' is not one of world, camera"), std::string::npos) << e.what();
  }
}

// A GLSL node written at mediump makes the scene's march half when the file names no precision of its own, and a
// scene precision given in the file decides for its GLSL fields. Broken variant: the node's mediump left to the
// node alone (sdf-node-mediump-not-the-scenes).
TEST(SceneFile, AGlslNodesMediumpIsTheScenesPrecision) {
  const std::string node = R"({"type": "glsl", "code": "float map(vec3 p) { return length(p) - 1.0; }", "kind": "exact", "precision": "half"})";
  EXPECT_EQ(scene_from_json(R"({"name": "h", "sdf": )" + node + "}", "h.json").march.precision, Precision::float16);
  const Scene in_float = scene_from_json(R"({"name": "h", "precision": "float", "sdf": )" + node + "}", "h.json");
  EXPECT_EQ(in_float.march.precision, Precision::float32);
  EXPECT_FALSE(in_float.root.glsl->spec().half);
}

TEST(SceneFile, SyntaxErrorsGiveLineAndColumn) {
  const std::string err = error_of("{\n  \"sdf\": {\"type\": \"sphere\",\n  \"radius\": 1,,\n}}");
  EXPECT_EQ(err.rfind("bad.json:3:15: syntax error", 0), 0u) << err;
}

TEST(SceneFile, ContentErrorsGiveTheJsonPathAndWhatWasExpected) {
  EXPECT_EQ(error_of(R"({"sdf": {"type": "sphere", "radus": 1}})"), "bad.json: /sdf: sphere needs \"radius\"");
  EXPECT_EQ(error_of(R"({"sdf": {"type": "sphere", "radius": 1, "radus": 1}})"),
            "bad.json: /sdf/radus: unknown key for sphere; expected one of type, material, radius");
  EXPECT_EQ(error_of(R"({"sdf": {"type": "sphere", "radius": "1"}})"),
            "bad.json: /sdf/radius: expected a number, got string");
  EXPECT_EQ(error_of(R"({"sdf": {"type": "sphere", "radius": -2}})"),
            "bad.json: /sdf/radius: value -2 is out of range [1e-12, 1e+300]");
  EXPECT_EQ(error_of(R"({"sdf": {"type": "union", "children": [{"type": "sphere", "radius": 1, "material": "gold"}]}})"),
            "bad.json: /sdf/children/0/material: no material named 'gold'");
  EXPECT_EQ(error_of(R"({"max_steps": 1.5, "sdf": {"type": "sphere", "radius": 1}})"),
            "bad.json: /max_steps: expected a whole number");
  EXPECT_EQ(error_of(R"({"marcher": "magic", "sdf": {"type": "sphere", "radius": 1}})"),
            "bad.json: /marcher: 'magic' is not one of sphere, relaxed, fixed, scaled");
  EXPECT_EQ(error_of(R"({"camera": {"fov": 60}, "sdf": {"type": "sphere", "radius": 1}})").substr(0, 48),
            "bad.json: /camera/fov: unknown key; expected one");
  EXPECT_EQ(error_of(R"({"sdf": {"type": "revolve", "child": {"type": "sphere", "radius": 1}}})"),
            "bad.json: /sdf/child: revolve needs a 2D child, sphere is 3D");
  EXPECT_EQ(error_of(R"({"name": "x"})"), "bad.json: : missing \"sdf\" (the scene's shape tree)");
}

TEST(SceneFile, OutOfRangeAndWronglyTypedValuesNameTheRange) {
  const std::string sphere = R"("sdf": {"type": "sphere", "radius": 1})";
  // hit_eps = 0 can never be reached by a float march: the range is open at 0.
  EXPECT_EQ(error_of(R"({"hit_eps": 0, )" + sphere + "}"), "bad.json: /hit_eps: value 0 is out of range (0, 1e+06]");
  EXPECT_EQ(error_of(R"({"hit_eps": -1e-3, )" + sphere + "}"),
            "bad.json: /hit_eps: value -0.001 is out of range (0, 1e+06]");
  EXPECT_EQ(error_of(R"({"max_steps": -1, )" + sphere + "}"),
            "bad.json: /max_steps: value -1 is out of range [0, 1.67772e+07]");
  EXPECT_EQ(error_of(R"({"camera": 3, )" + sphere + "}"), "bad.json: /camera: expected an object");
  EXPECT_EQ(error_of(R"({"lights": {}, )" + sphere + "}"), "bad.json: /lights: expected an array");
  EXPECT_EQ(error_of(R"({"camera": {"position": [0, 1]}, )" + sphere + "}"),
            "bad.json: /camera/position: expected an array of 3 numbers");
  EXPECT_EQ(error_of(R"({"normal_eps_scaled": 1, )" + sphere + "}"),
            "bad.json: /normal_eps_scaled: expected true or false");
  EXPECT_EQ(error_of(R"({"sdf": {"type": "box", "half_size": [1, -0.25, 1]}})"),
            "bad.json: /sdf/half_size/1: value -0.25 is out of range [1e-12, 1e+300]");
  EXPECT_EQ(error_of(R"({"meshes": [{"vertices": [], "triangles": []}], )" + sphere + "}"),
            "bad.json: /meshes/0: needs at least one triangle");
  // Found by fuzz_scene: the JSON parser's overflow error has no position and escaped as another exception type.
  EXPECT_EQ(error_of("{\"hit_eps\": 1e3080, " + sphere + "}"),
            "bad.json:1:13: the number 1e3080 is beyond the range of a double");
  EXPECT_EQ(error_of("{\n \"sdf\": {\"type\": \"sphere\", \"radius\": -22222222222e2222222222222}}"),
            "bad.json:2:38: the number -22222222222e2222222222222 is beyond the range of a double");
  // A step of more than twice f is no marcher's: refused.
  EXPECT_EQ(error_of(R"({"step_scale": 2.5, )" + sphere + "}"), "bad.json: /step_scale: value 2.5 is out of range [1e-06, 2]");
  // The relaxed marcher takes [1, 2): a file asking for 2 is refused at load, not marched into `invalid` on every
  // ray (the drift this pins: the file accepted [1, 2], the marcher [1, 2)). --set goes through the same range.
  EXPECT_EQ(error_of(R"({"relaxation": 2, )" + sphere + "}"), "bad.json: /relaxation: value 2 is out of range [1, 2)");
  Scene scene;
  EXPECT_THROW(apply_setting(scene, "relaxation", "2"), SceneError);
  EXPECT_NO_THROW(apply_setting(scene, "relaxation", "1.999"));
  // JSON has no NaN literal: it is a syntax error at its place.
  EXPECT_EQ(error_of("{\"hit_eps\": NaN, " + sphere + "}").rfind("bad.json:1:13: syntax error", 0), 0u);
}

TEST(SceneFile, DeepNestingIsRefused) {
  std::string text = R"({"sdf": )";
  for (int i = 0; i < 100; ++i) text += R"({"type": "round", "radius": 0, "child": )";
  text += R"({"type": "sphere", "radius": 1})";
  for (int i = 0; i < 100; ++i) text += "}";
  text += "}";
  EXPECT_NE(error_of(text).find("nests deeper than 64 levels"), std::string::npos);
}

// A scene file beside a mesh file, in a folder of its own.
class MeshScene : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("marchcheck_mesh_scene_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    meshes::save_mesh(meshes::notched_box({1, 0.7, 0.6}).mesh, (dir_ / "notched.obj").string());
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& sdf) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << R"({"name": "m", "sdf": )" << sdf << "}";
    return path;
  }
  static std::string error_of(const std::string& path, const MeshLoader& loader = meshes::load_mesh_source) {
    try {
      load_scene_file(path, loader);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "(no error)";
  }
  std::filesystem::path dir_;
};

// A material's texture_file is found beside the scene file (and exported resolved); a missing one, or one without
// a texture mapping to put it on, is refused naming the JSON place and the file. Broken variants: the path taken
// from the working folder; a missing file accepted (the soil drawn in its place).
TEST_F(MeshScene, ATextureFileIsFoundBesideTheSceneFileOrRefused) {
  std::ofstream(dir_ / "soil.png") << "not checked here: march reads it";
  const auto scene_with = [&](const std::string& name, const std::string& material) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << R"({"sdf": {"type": "sphere", "radius": 1}, "materials": [)" << material << "]}";
    return path;
  };
  const Scene s = load_scene_file(scene_with("t.json", R"({"name": "g", "texture": "planar", "texture_file": "soil.png"})"));
  EXPECT_EQ(s.materials.at(0).texture_file, (dir_ / "soil.png").string());
  EXPECT_EQ(load_scene_file(scene_with("again.json", "")).materials.size(), 0u);
  const std::string missing = scene_with("m.json", R"({"name": "g", "texture": "planar", "texture_file": "nowhere.png"})");
  EXPECT_EQ(error_of(missing), missing + ": /materials/0/texture_file: '" + (dir_ / "nowhere.png").string() +
                                   "': no such file");
  const std::string unmapped = scene_with("u.json", R"({"name": "g", "texture_file": "soil.png"})");
  EXPECT_NE(error_of(unmapped).find("/materials/0/texture_file: an image needs a \"texture\" mapping"),
            std::string::npos)
      << error_of(unmapped);
}

// Broken variant: load_scene_file without the default leaves the name empty (render printed ": 32x18, ...").
TEST_F(MeshScene, AFileWithoutANameGoesByItsFileName) {
  const std::string path = (dir_ / "unnamed part.json").string();
  std::ofstream(path) << R"({"sdf": {"type": "sphere", "radius": 1}})";
  EXPECT_EQ(load_scene_file(path).name, "unnamed part");
  EXPECT_EQ(load_scene_file(write("named.json", R"({"type": "sphere", "radius": 1})")).name, "m");
}

TEST_F(MeshScene, ShorthandPathIsFoundBesideTheSceneFileAndRoundTrips) {
  const std::string path = write("scene.json", R"({"type": "translate", "offset": [0, 1, 0], "child": {"mesh": "notched.obj"}})");
  const Scene s = load_scene_file(path);
  const Node& m = s.root.children[0];
  ASSERT_EQ(m.op, Op::mesh);
  EXPECT_EQ(m.source, (dir_ / "notched.obj").string());
  ASSERT_TRUE(m.mesh);
  EXPECT_EQ(m.mesh->mesh().triangles.size(), 48u);
  EXPECT_EQ(derive_info(s.root).kind, Kind::exact);
  // Exported with the resolved path: the file loads the same from any folder, and exports the same again.
  const std::string text = scene_to_json(s);
  const Scene again = scene_from_json(text, "elsewhere/exported.json");
  EXPECT_EQ(scene_to_json(again), text);
  EXPECT_EQ(evaluate(compile(again.root), glm::dvec3(0.3, 1.2, 0.1)), evaluate(compile(s.root), glm::dvec3(0.3, 1.2, 0.1)));
}

TEST_F(MeshScene, MissingOrBadMeshesAndNoLoaderNameTheFileAndTheJsonPath) {
  const std::string missing = write("missing.json", R"({"type": "union", "children": [{"mesh": "nowhere.obj"}]})");
  const std::string err = error_of(missing);
  EXPECT_EQ(err.rfind(missing + ": /sdf/children/0/mesh: ", 0), 0u) << err;
  EXPECT_NE(err.find((dir_ / "nowhere.obj").string()), std::string::npos) << err;

  meshes::Mesh open = meshes::box({1, 1, 1}).mesh;
  open.triangles.pop_back();
  meshes::save_mesh(open, (dir_ / "open.off").string());
  const std::string bad = write("bad.json", R"({"mesh": "open.off"})");
  const std::string bad_err = error_of(bad);
  EXPECT_EQ(bad_err.rfind(bad + ": /sdf/mesh: '" + (dir_ / "open.off").string() + "': open: ", 0), 0u) << bad_err;
  EXPECT_NE(bad_err.find("boundary edges"), std::string::npos) << bad_err;

  const std::string good = write("good.json", R"({"mesh": "notched.obj"})");
  EXPECT_NE(error_of(good, {}).find(good + ": /sdf/mesh: '"), std::string::npos);
  EXPECT_NE(error_of(good, {}).find("no mesh loader"), std::string::npos);
  EXPECT_NE(error_of(write("gen.json", R"j({"mesh": "procedural:icosphere(1,99)"})j"))
                .find("/sdf/mesh: procedural:icosphere(1,99)"),
            std::string::npos);
  EXPECT_THROW(builtin_scene("mesh-icosphere", {}), SceneError);  // built-ins with meshes need a loader too
}

// A mesh with a split seam (corner 7 doubled, 200 zero-area slivers along it): refused as read, taken with
// "weld", which says what it changed. Broken variants: weld ignored; meshes cached by file alone (the welded and
// the unwelded node would share one); nothing said.
TEST_F(MeshScene, AWeldClosesASplitSeamAndSaysWhatItChanged) {
  meshes::Mesh m = meshes::box({1, 1, 1}).mesh;
  const auto copy = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.push_back(m.vertices[7]);
  m.triangles[11][1] = copy;
  for (int i = 0; i < 200; ++i) m.triangles.push_back({7, copy, 3});
  meshes::save_mesh(m, (dir_ / "seam.obj").string());
  const std::string mesh = (dir_ / "seam.obj").string();
  EXPECT_NE(error_of(write("raw.json", R"({"mesh": "seam.obj"})")).find("'" + mesh + "': 200 degenerate faces"),
            std::string::npos);
  const Scene s = load_scene_file(write("welded.json", R"({"mesh": "seam.obj", "weld": 1e-9})"));
  ASSERT_TRUE(s.root.mesh);
  EXPECT_EQ(s.root.mesh->mesh().triangles.size(), 12u);
  EXPECT_EQ(mesh_notes(s.root),
            std::vector<std::string>{"mesh '" + mesh + "' welded at 1e-09: 1 vertices merged, 200 faces with a "
                                     "repeated index removed"});
  const std::string both = write("both.json", R"({"type": "union", "children": [{"mesh": "seam.obj", "weld": 1e-9},
                                                  {"mesh": "seam.obj"}]})");
  EXPECT_NE(error_of(both).find("/sdf/children/1/mesh: '" + mesh + "': 200 degenerate faces"), std::string::npos)
      << error_of(both);
  EXPECT_NE(error_of(write("neg.json", R"({"mesh": "seam.obj", "weld": -1})")).find("/sdf/weld"), std::string::npos);
}

// 10000 nested nodes, and a million nested arrays anywhere in the file: an error, not a stack overflow (the
// JSON parser and its destructor are iterative; the tree reader stops at 64 levels).
TEST(SceneFile, VeryDeepNestingGivesAnErrorNotAStackOverflow) {
  std::string text = R"({"sdf": )";
  for (int i = 0; i < 10000; ++i) text += R"({"type": "round", "radius": 0, "child": )";
  text += R"({"type": "sphere", "radius": 1})" + std::string(10001, '}');
  EXPECT_EQ(error_of(text).rfind("bad.json: /sdf/child/child/", 0), 0u);
  EXPECT_NE(error_of(text).find(": the tree nests deeper than 64 levels"), std::string::npos);
  const std::string arrays = R"({"limits": )" + std::string(1000000, '[') + std::string(1000000, ']') + "}";
  EXPECT_EQ(error_of(arrays), "bad.json: /limits: expected an object of metric names to numbers");
}

TEST(Settings, OverridesParseTypedValuesAndRejectBadOnes) {
  Scene s = builtin_scene("lee-flat");
  apply_setting(s, "max_steps", "64");
  apply_setting(s, "marcher", "relaxed");
  apply_setting(s, "camera.target", "0,1,0");
  apply_setting(s, "max_dist", "inf");
  EXPECT_EQ(s.march.max_steps, 64);
  EXPECT_EQ(s.march.marcher, Marcher::relaxed);
  EXPECT_EQ(s.camera.target, glm::dvec3(0, 1, 0));
  EXPECT_TRUE(std::isinf(s.march.max_dist));
  EXPECT_THROW(apply_setting(s, "max_step", "64"), SceneError);
  EXPECT_THROW(apply_setting(s, "max_steps", "many"), SceneError);
  EXPECT_THROW(apply_setting(s, "hit_eps", "-1"), SceneError);
}

std::string setting_error(const std::string& key, const std::string& value) {
  Scene s = builtin_scene("lee-flat");
  try {
    apply_setting(s, key, value);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

// setting_text reads a setting back as apply_setting takes it, exactly: a sweep's first point is the scene's own
// settings. Broken variant: numbers printed to six decimals (sdf-setting-text-rounded).
TEST(Settings, TextReadBackAppliesToTheSameValue) {
  Scene scene = builtin_scene("lee-flat");
  apply_setting(scene, "hit_eps", "0.0123456789012345");
  apply_setting(scene, "refine", "secant");
  apply_setting(scene, "clip", "bounds");
  EXPECT_EQ(setting_text(scene, "clip"), "bounds");
  apply_setting(scene, "step_bound", "perturbed");
  EXPECT_EQ(scene.march.step_bound, StepBound::perturbed);
  EXPECT_EQ(setting_text(scene, "step_bound"), "perturbed");
  EXPECT_EQ(setting_text(scene, "hit_eps"), "0.0123456789012345");
  EXPECT_EQ(setting_text(scene, "refine"), "secant");
  EXPECT_EQ(setting_text(scene, "max_steps"), "200");
  for (const char* key : {"hit_eps", "max_steps", "marcher", "relaxation", "camera.fov_deg", "time"}) {
    Scene again = builtin_scene("crum-torus");
    apply_setting(again, key, setting_text(scene, key));
    EXPECT_EQ(setting_text(again, key), setting_text(scene, key)) << key;
  }
  EXPECT_THROW(setting_text(scene, "no_such_key"), SceneError);
  EXPECT_THROW(setting_text(scene, "shadow"), SceneError);  // every light's: no one value
}

TEST(Settings, BadValuesNameTheKeyTheValueAndWhatWasExpected) {
  EXPECT_EQ(setting_error("hit_eps", "nan"), "hit_eps=nan: expected a number, got NaN");
  EXPECT_EQ(setting_error("hit_eps", "0"), "hit_eps=0: value 0 is out of range (0, 1e+06]");
  EXPECT_EQ(setting_error("max_steps", "-1"), "max_steps=-1: value -1 is out of range [0, 1.67772e+07]");
  EXPECT_EQ(setting_error("max_steps", "1e9"), "max_steps=1e9: value 1e+09 is out of range [0, 1.67772e+07]");
  EXPECT_EQ(setting_error("marcher", "3"), "marcher=3: expected one of sphere, relaxed, fixed, scaled");
  EXPECT_EQ(setting_error("clip", "box"), "clip=box: 'box' is not one of none, bounds");
  EXPECT_EQ(setting_error("step_bound", "local"), "step_bound=local: 'local' is not one of lipschitz, perturbed");
  EXPECT_EQ(setting_error("camera.target", "0,1"), "camera.target=0,1: expected an array of 3 numbers");
  EXPECT_EQ(setting_error("max_dist", "-inf"), "max_dist=-inf: value -inf is out of range [0, inf]");
  EXPECT_EQ(setting_error("max_dist", "inf"), "(no error)");  // the broken-variant guard: good values pass
  EXPECT_EQ(setting_error("hit_eps", "1e-4"), "(no error)");
}

}  // namespace
}  // namespace marchcheck::sdf
