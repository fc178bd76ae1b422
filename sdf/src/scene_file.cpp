#include "marchcheck/sdf/scene_file.hpp"

#include "marchcheck/meshes/weld.hpp"

#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/mesh_distance.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

namespace marchcheck::sdf {

using json = nlohmann::ordered_json;

namespace {

constexpr int kMaxTreeDepth = 64;

[[noreturn]] void fail(const std::string& where, const std::string& what) { throw SceneError(where + ": " + what); }

template <class E>
struct EnumName {
  E value;
  const char* name;
};

constexpr EnumName<Marcher> kMarchers[] = {
    {Marcher::sphere, "sphere"}, {Marcher::relaxed, "relaxed"}, {Marcher::fixed, "fixed"}, {Marcher::scaled, "scaled"}};
constexpr EnumName<HitRefine> kHitRefines[] = {{HitRefine::none, "none"}, {HitRefine::secant, "secant"}};
constexpr EnumName<Clip> kClips[] = {{Clip::none, "none"}, {Clip::bounds, "bounds"}};
constexpr EnumName<StepBound> kStepBounds[] = {{StepBound::lipschitz, "lipschitz"}, {StepBound::perturbed, "perturbed"}};
constexpr EnumName<EpsMode> kEpsModes[] = {
    {EpsMode::absolute, "absolute"}, {EpsMode::relative, "relative"}, {EpsMode::pixel, "pixel"}};
constexpr EnumName<NormalMethod> kNormals[] = {{NormalMethod::central, "central"},
                                               {NormalMethod::forward, "forward"},
                                               {NormalMethod::tetra, "tetra"},
                                               {NormalMethod::analytic, "analytic"}};
constexpr EnumName<ShadowMode> kShadows[] = {
    {ShadowMode::none, "none"}, {ShadowMode::hard, "hard"}, {ShadowMode::soft, "soft"}};
constexpr EnumName<Precision> kPrecisions[] = {{Precision::float32, "float"}, {Precision::float64, "double"}, {Precision::float16, "half"}};
constexpr EnumName<CameraModel> kCameraModels[] = {{CameraModel::pinhole, "pinhole"},
                                                   {CameraModel::intrinsics, "intrinsics"},
                                                   {CameraModel::frustum, "frustum"},
                                                   {CameraModel::orthographic, "orthographic"}};
constexpr EnumName<CameraAxes> kCameraAxes[] = {{CameraAxes::right_handed, "right_handed"},
                                                {CameraAxes::shader, "shader"}};
constexpr EnumName<LensConvention> kLenses[] = {{LensConvention::opencv, "opencv"}, {LensConvention::shader, "shader"}};
constexpr EnumName<RecordReading> kReadings[] = {{RecordReading::outcome, "outcome"},
                                                  {RecordReading::seed_distance, "seed_distance"},
                                                  {RecordReading::seed_infinity, "seed_infinity"}};
constexpr EnumName<Coordinates> kCoordinates[] = {{Coordinates::world, "world"}, {Coordinates::camera, "camera"}};
constexpr EnumName<OutputTransfer> kTransfers[] = {{OutputTransfer::srgb, "srgb"}, {OutputTransfer::linear, "linear"}};
constexpr EnumName<CameraPose> kCameraPoses[] = {{CameraPose::look_at, "look_at"}, {CameraPose::orbit, "orbit"}};
constexpr EnumName<LightType> kLightTypes[] = {{LightType::point, "point"}, {LightType::directional, "directional"}};

template <class E, size_t N>
std::string enum_name(const EnumName<E> (&table)[N], E value) {
  for (const auto& e : table)
    if (e.value == value) return e.name;
  return "?";
}

template <class E, size_t N>
E enum_value(const EnumName<E> (&table)[N], const json& v, const std::string& where) {
  std::string names;
  for (const auto& e : table) names += std::string(names.empty() ? "" : ", ") + e.name;
  if (!v.is_string()) fail(where, "expected one of " + names);
  for (const auto& e : table)
    if (v.get<std::string>() == e.name) return e.value;
  fail(where, "'" + v.get<std::string>() + "' is not one of " + names);
}

// JSON has no infinity: scene files spell it "inf" (max_dist, for instance).
json number_json(double x) { return std::isinf(x) ? json(x > 0 ? "inf" : "-inf") : json(x); }

// above_lo: the range excludes lo itself (a tolerance such as hit_eps must be > 0, not >= 0).
double number(const json& v, const std::string& where, double lo = -1e300, double hi = 1e300, bool above_lo = false,
              bool below_hi = false) {
  const bool infinite = v.is_string() && (v.get<std::string>() == "inf" || v.get<std::string>() == "-inf");
  if (!v.is_number() && !infinite) fail(where, "expected a number, got " + std::string(v.type_name()));
  const double x = infinite ? (v.get<std::string>() == "inf" ? INFINITY : -INFINITY) : v.get<double>();
  if (std::isnan(x)) fail(where, "expected a number, got NaN");  // only --set can spell it
  if (!(x >= lo && x <= hi) || (above_lo && x == lo) || (below_hi && x == hi)) {
    std::ostringstream s;
    s << "value " << x << " is out of range " << (above_lo ? "(" : "[") << lo << ", " << hi << (below_hi ? ")" : "]");
    fail(where, s.str());
  }
  return x;
}

int integer(const json& v, const std::string& where, int lo, int hi) {
  const double x = number(v, where, lo, hi);
  if (x != static_cast<int>(x)) fail(where, "expected a whole number");
  return static_cast<int>(x);
}

glm::dvec3 vec3(const json& v, const std::string& where) {
  if (!v.is_array() || v.size() != 3) fail(where, "expected an array of 3 numbers");
  return {number(v[0], where + "/0"), number(v[1], where + "/1"), number(v[2], where + "/2")};
}
json vec3_json(glm::dvec3 v) { return json::array({v.x, v.y, v.z}); }

constexpr EnumName<ShadowBias> kBiases[] = {
    {ShadowBias::seed_offset, "seed_offset"}, {ShadowBias::seed_ignore, "seed_ignore"}, {ShadowBias::scaled, "scaled"}};
constexpr EnumName<SoftShadow> kSoftShadows[] = {{SoftShadow::classic, "classic"}, {SoftShadow::improved, "improved"}};
constexpr EnumName<SpecularModel> kSpeculars[] = {
    {SpecularModel::none, "none"}, {SpecularModel::phong, "phong"}, {SpecularModel::blinn, "blinn"}};
constexpr EnumName<TextureMapping> kTextures[] = {
    {TextureMapping::none, "none"}, {TextureMapping::planar, "planar"}, {TextureMapping::spherical, "spherical"}};
constexpr EnumName<Diffuse> kDiffuse[] = {
    {Diffuse::clamped, "clamped"}, {Diffuse::floor, "floor"}, {Diffuse::unclamped, "unclamped"}};
constexpr EnumName<AmbientOcclusion> kAo[] = {
    {AmbientOcclusion::none, "none"}, {AmbientOcclusion::steps, "steps"}, {AmbientOcclusion::samples, "samples"}};
constexpr EnumName<Shading> kShading[] = {{Shading::lambert, "lambert"}, {Shading::toon, "toon"}};

// One settable key of a struct S (the scene, a light, a material): getter and setter through JSON. One table
// drives --set, reading scene files and writing them, so the three never disagree. A field without a getter
// is an override (--set only) and is not written.
template <class S>
struct Field {
  std::string key;
  std::function<json(const S&)> get;
  std::function<void(S&, const json&, const std::string&)> set;
};

template <class S, class E, size_t N, class M>
Field<S> enum_field(std::string key, const EnumName<E> (&table)[N], M member) {
  return {key, [&table, member](const S& s) { return json(enum_name(table, member(const_cast<S&>(s)))); },
          [&table, member](S& s, const json& v, const std::string& w) { member(s) = enum_value(table, v, w); }};
}
template <class S, class M>
Field<S> number_field(std::string key, M member, double lo, double hi, bool above_lo = false, bool below_hi = false) {
  return {key, [member](const S& s) { return number_json(member(const_cast<S&>(s))); },
          [member, lo, hi, above_lo, below_hi](S& s, const json& v, const std::string& w) {
            member(s) = number(v, w, lo, hi, above_lo, below_hi);
          }};
}
template <class S, class M>
Field<S> int_field(std::string key, M member, int lo, int hi) {
  return {key, [member](const S& s) { return json(member(const_cast<S&>(s))); },
          [member, lo, hi](S& s, const json& v, const std::string& w) { member(s) = integer(v, w, lo, hi); }};
}
template <class S, class M>
Field<S> vec3_field(std::string key, M member) {
  return {key, [member](const S& s) { return vec3_json(member(const_cast<S&>(s))); },
          [member](S& s, const json& v, const std::string& w) { member(s) = vec3(v, w); }};
}
template <class S, class M>
Field<S> bool_field(std::string key, M member) {
  return {key, [member](const S& s) { return json(member(const_cast<S&>(s))); },
          [member](S& s, const json& v, const std::string& w) {
            if (!v.is_boolean()) fail(w, "expected true or false");
            member(s) = v.get<bool>();
          }};
}

#define MEMBER(S, expr) [](S& s) -> auto& { return s.expr; }

const std::vector<Field<Light>>& light_fields() {
  static const std::vector<Field<Light>> table = {
      enum_field<Light>("type", kLightTypes, MEMBER(Light, type)),
      vec3_field<Light>("position", MEMBER(Light, position)),
      vec3_field<Light>("direction", MEMBER(Light, direction)),
      vec3_field<Light>("color", MEMBER(Light, color)),
      vec3_field<Light>("motion_sin", MEMBER(Light, motion_sin)),
      vec3_field<Light>("motion_cos", MEMBER(Light, motion_cos)),
      // One rate for every axis, or one per axis.
      {"motion_rate",
       [](const Light& l) {
         const glm::dvec3 r = l.motion_rate;
         return r.x == r.y && r.y == r.z ? number_json(r.x) : vec3_json(r);
       },
       [](Light& l, const json& v, const std::string& w) {
         l.motion_rate = v.is_array() ? vec3(v, w) : glm::dvec3(number(v, w, -1e6, 1e6));
       }},
      enum_field<Light>("shadow", kShadows, MEMBER(Light, shadow)),
      enum_field<Light>("bias", kBiases, MEMBER(Light, bias)),
      number_field<Light>("bias_factor", MEMBER(Light, bias_factor), 0, 1e6),
      number_field<Light>("darkening", MEMBER(Light, darkening), 0, 1),
      bool_field<Light>("specular_in_shadow", MEMBER(Light, specular_in_shadow)),
      enum_field<Light>("soft", kSoftShadows, MEMBER(Light, soft)),
      number_field<Light>("penumbra", MEMBER(Light, penumbra), 1e-3, 1e6),
  };
  return table;
}

const std::vector<Field<Material>>& material_fields() {
  static const std::vector<Field<Material>> table = {
      {"name", [](const Material& m) { return json(m.name); },
       [](Material& m, const json& v, const std::string& w) {
         if (!v.is_string()) fail(w, "expected a string");
         m.name = v.get<std::string>();
       }},
      vec3_field<Material>("color", MEMBER(Material, color)),
      enum_field<Material>("specular", kSpeculars, MEMBER(Material, specular)),
      number_field<Material>("specular_strength", MEMBER(Material, specular_strength), 0, 1e3),
      number_field<Material>("shininess", MEMBER(Material, shininess), 0, 1e5),
      number_field<Material>("reflectivity", MEMBER(Material, reflectivity), 0, 1),
      number_field<Material>("transparency", MEMBER(Material, transparency), 0, 1),
      number_field<Material>("ior", MEMBER(Material, ior), 1, 4),
      number_field<Material>("density", MEMBER(Material, density), 0, 1e6),
      enum_field<Material>("texture", kTextures, MEMBER(Material, texture)),
      number_field<Material>("texture_scale", MEMBER(Material, texture_scale), 1e-9, 1e9),
      vec3_field<Material>("texture_origin", MEMBER(Material, texture_origin)),
      {"texture_file", [](const Material& m) { return json(m.texture_file); },
       [](Material& m, const json& v, const std::string& w) {
         if (!v.is_string()) fail(w, "expected a path");
         m.texture_file = v.get<std::string>();
       }},
      number_field<Material>("ramp_value", MEMBER(Material, ramp_value), -1, 1),
  };
  return table;
}

// The GLSL fields of a tree, each given to f (a std::shared_ptr<const GlslField>&, const where the tree is).
template <class N, class F>
void each_glsl_field(N& n, F&& f) {
  if (n.op == Op::glsl) f(n.glsl);
  for (N& c : n.children) each_glsl_field(c, f);
}

// precision: the march's float, double or half; the scene's GLSL fields follow it (binary16 in half, else float).
void set_precision(Scene& s, const json& v, const std::string& where) {
  s.march.precision = enum_value(kPrecisions, v, where);
  each_glsl_field(s.root, [&](std::shared_ptr<const GlslField>& field) {
    field = std::make_shared<const GlslField>(field->with_half(s.march.precision == Precision::float16));
  });
}

const std::vector<Field<Scene>>& settings() {
  static const std::vector<Field<Scene>> table = {
      enum_field<Scene>("marcher", kMarchers, MEMBER(Scene, march.marcher)),
      int_field<Scene>("max_steps", MEMBER(Scene, march.max_steps), 0, 1 << 24),
      number_field<Scene>("max_dist", MEMBER(Scene, march.max_dist), 0, INFINITY),
      number_field<Scene>("hit_eps", MEMBER(Scene, march.hit_eps), 0, 1e6, true),
      enum_field<Scene>("eps_mode", kEpsModes, MEMBER(Scene, march.eps_mode)),
      enum_field<Scene>("refine", kHitRefines, MEMBER(Scene, march.refine)),
      enum_field<Scene>("clip", kClips, MEMBER(Scene, march.clip)),
      enum_field<Scene>("step_bound", kStepBounds, MEMBER(Scene, march.step_bound)),
      number_field<Scene>("step_scale", MEMBER(Scene, march.step_scale), 1e-6, 2),
      number_field<Scene>("relaxation", MEMBER(Scene, march.relaxation), kRelaxationMin, kRelaxationMax, false, true),
      number_field<Scene>("fixed_step", MEMBER(Scene, march.fixed_step), 1e-9, 1e6),
      enum_field<Scene>("normal", kNormals, MEMBER(Scene, march.normal)),
      number_field<Scene>("normal_eps", MEMBER(Scene, march.normal_eps), 1e-12, 1),
      bool_field<Scene>("normal_eps_scaled", MEMBER(Scene, march.normal_eps_scaled)),
      {"precision", [](const Scene& s) { return json(enum_name(kPrecisions, s.march.precision)); }, set_precision},
      enum_field<Scene>("reading", kReadings, MEMBER(Scene, march.reading)),
      enum_field<Scene>("coordinates", kCoordinates, MEMBER(Scene, march.coordinates)),
      // Overrides for every light at once.
      {"shadow", nullptr,
       [](Scene& s, const json& v, const std::string& w) {
         for (auto& l : s.lights) l.shadow = enum_value(kShadows, v, w);
       }},
      {"shadow_bias", nullptr,
       [](Scene& s, const json& v, const std::string& w) {
         for (auto& l : s.lights) l.bias = enum_value(kBiases, v, w);
       }},
      number_field<Scene>("time", MEMBER(Scene, time), -1e6, 1e6),
      int_field<Scene>("width", MEMBER(Scene, width), 1, 16384),
      int_field<Scene>("height", MEMBER(Scene, height), 1, 16384),
      enum_field<Scene>("camera.model", kCameraModels, MEMBER(Scene, camera.model)),
      enum_field<Scene>("camera.pose", kCameraPoses, MEMBER(Scene, camera.pose)),
      vec3_field<Scene>("camera.position", MEMBER(Scene, camera.position)),
      vec3_field<Scene>("camera.target", MEMBER(Scene, camera.target)),
      vec3_field<Scene>("camera.up", MEMBER(Scene, camera.up)),
      number_field<Scene>("camera.yaw_deg", MEMBER(Scene, camera.yaw_deg), -1e6, 1e6),
      number_field<Scene>("camera.pitch_deg", MEMBER(Scene, camera.pitch_deg), -89.9, 89.9),
      number_field<Scene>("camera.distance", MEMBER(Scene, camera.distance), 1e-9, 1e12),
      number_field<Scene>("camera.fov_deg", MEMBER(Scene, camera.fov_deg), 1e-3, 179),
      number_field<Scene>("camera.fx", MEMBER(Scene, camera.fx), 1e-6, 1e9),
      number_field<Scene>("camera.fy", MEMBER(Scene, camera.fy), 1e-6, 1e9),
      number_field<Scene>("camera.cx", MEMBER(Scene, camera.cx), -1, 1e9),
      number_field<Scene>("camera.cy", MEMBER(Scene, camera.cy), -1, 1e9),
      number_field<Scene>("camera.k1", MEMBER(Scene, camera.k1), -10, 10),
      number_field<Scene>("camera.k2", MEMBER(Scene, camera.k2), -10, 10),
      number_field<Scene>("camera.p1", MEMBER(Scene, camera.p1), -10, 10),
      number_field<Scene>("camera.p2", MEMBER(Scene, camera.p2), -10, 10),
      number_field<Scene>("camera.ortho_height", MEMBER(Scene, camera.ortho_height), 1e-12, 1e12),
      bool_field<Scene>("camera.fov_full_height", MEMBER(Scene, camera.fov_full_height)),
      bool_field<Scene>("camera.normalize_rays", MEMBER(Scene, camera.normalize_rays)),
      enum_field<Scene>("camera.axes", kCameraAxes, MEMBER(Scene, camera.axes)),
      enum_field<Scene>("camera.lens", kLenses, MEMBER(Scene, camera.lens)),
      vec3_field<Scene>("effects.background", MEMBER(Scene, effects.background)),
      number_field<Scene>("effects.ambient", MEMBER(Scene, effects.ambient), 0, 1),
      enum_field<Scene>("effects.diffuse", kDiffuse, MEMBER(Scene, effects.diffuse)),
      number_field<Scene>("effects.diffuse_floor", MEMBER(Scene, effects.diffuse_floor), 0, 1),
      enum_field<Scene>("effects.shading", kShading, MEMBER(Scene, effects.shading)),
      int_field<Scene>("effects.toon_bands", MEMBER(Scene, effects.toon_bands), 2, 64),
      number_field<Scene>("effects.silhouette", MEMBER(Scene, effects.silhouette), 0, 1),
      enum_field<Scene>("effects.ao", kAo, MEMBER(Scene, effects.ao)),
      number_field<Scene>("effects.ao_steps_scale", MEMBER(Scene, effects.ao_steps_scale), 0, 1),
      int_field<Scene>("effects.ao_samples", MEMBER(Scene, effects.ao_samples), 1, 64),
      number_field<Scene>("effects.ao_distance", MEMBER(Scene, effects.ao_distance), 1e-9, 1e9),
      number_field<Scene>("effects.glow", MEMBER(Scene, effects.glow), 0, 1e3),
      number_field<Scene>("effects.glow_width", MEMBER(Scene, effects.glow_width), 1e-9, 1e9),
      vec3_field<Scene>("effects.glow_color", MEMBER(Scene, effects.glow_color)),
      number_field<Scene>("effects.fog", MEMBER(Scene, effects.fog), 0, 1e6),
      vec3_field<Scene>("effects.fog_color", MEMBER(Scene, effects.fog_color)),
      int_field<Scene>("effects.max_bounces", MEMBER(Scene, effects.max_bounces), 0, 16),
      {"effects.ramp",
       [](const Scene& s) {
         json list = json::array();
         for (const auto& c : s.effects.ramp) list.push_back(vec3_json(c));
         return list;
       },
       [](Scene& s, const json& v, const std::string& w) {
         if (!v.is_array()) fail(w, "expected an array of colours");
         s.effects.ramp.clear();
         for (size_t i = 0; i < v.size(); ++i) s.effects.ramp.push_back(vec3(v[i], w + "/" + std::to_string(i)));
       }},
      bool_field<Scene>("effects.eye_is_ray_direction", MEMBER(Scene, effects.eye_is_ray_direction)),
      enum_field<Scene>("output_transfer", kTransfers, MEMBER(Scene, output_transfer)),
  };
  return table;
}

#undef MEMBER

const Field<Scene>* find_setting(std::string_view key) {
  for (const auto& s : settings())
    if (s.key == key) return &s;
  return nullptr;
}

// The settings of one section ("" = top-level keys without a dot) that scene files carry.
std::vector<const Field<Scene>*> section(std::string_view prefix) {
  std::vector<const Field<Scene>*> out;
  for (const auto& s : settings()) {
    const auto dot = s.key.find('.');
    const std::string_view head = dot == std::string::npos ? "" : std::string_view(s.key).substr(0, dot);
    if (head == prefix && s.get) out.push_back(&s);
  }
  return out;
}

template <class S>
json write_fields(const S& value, const std::vector<Field<S>>& fields) {
  json j = json::object();
  for (const auto& f : fields) j[f.key] = f.get(value);
  return j;
}

template <class S>
void read_fields(S& value, const json& j, const std::vector<Field<S>>& fields, const std::string& where) {
  if (!j.is_object()) fail(where, "expected an object");
  for (const auto& item : j.items()) {  // not a structured binding: clang 14 cannot capture one in a lambda
    const std::string& key = item.key();
    const json& v = item.value();
    auto f = std::find_if(fields.begin(), fields.end(), [&](const Field<S>& x) { return x.key == key; });
    if (f == fields.end()) {
      std::string expected;
      for (const auto& x : fields) expected += (expected.empty() ? "" : ", ") + x.key;
      fail(where + "/" + key, "unknown key; expected one of " + expected);
    }
    f->set(value, v, where + "/" + key);
  }
}

// A --set value as JSON: a number, true/false, a comma list of numbers, else a string.
json parse_setting_value(std::string_view text) {
  auto as_number = [](std::string_view t, double& out) {
    const auto* end = t.data() + t.size();
    auto [ptr, ec] = std::from_chars(t.data(), end, out);
    return ec == std::errc() && ptr == end;
  };
  double x;
  if (as_number(text, x)) return x;
  if (text == "inf" || text == "Inf") return INFINITY;
  if (text == "true") return true;
  if (text == "false") return false;
  if (text.find(',') != std::string_view::npos) {
    json list = json::array();
    size_t start = 0;
    while (start <= text.size()) {
      const size_t end = std::min(text.find(',', start), text.size());
      if (!as_number(text.substr(start, end - start), x)) return std::string(text);
      list.push_back(x);
      start = end + 1;
    }
    return list;
  }
  return std::string(text);
}

// ---------------------------------------------------------------- nodes

void glsl_to_json(const GlslSpec& spec, json& j, const Scene& scene) {
  if (spec.code.empty()) {
    j["source"] = spec.source;
  } else {
    j["code"] = spec.code;
  }
  j["function"] = spec.function;
  if (!spec.uniforms.empty()) {
    json u = json::object();
    for (const auto& [name, value] : spec.uniforms) u[name] = value.size() == 1 ? json(value[0]) : json(value);
    j["uniforms"] = u;
  }
  if (spec.half) j["precision"] = "half";
  if (!spec.materials.empty()) {
    json names = json::array();
    for (const int m : spec.materials) names.push_back(scene.materials.at(static_cast<size_t>(m)).name);
    j["materials"] = names;
  }
  j["kind"] = spec.measured ? "unknown" : std::string(to_string(spec.kind));
  if (!spec.measured && spec.kind == Kind::lipschitz) j["lipschitz"] = spec.lipschitz;
}

json node_to_json(const Node& n, const Scene& scene) {
  const auto& info = op_info(n.op);
  json j;
  j["type"] = std::string(info.name);
  for (const auto& spec : info.params) {
    const auto values = n.param(spec.name);
    if (spec.size == 1) {
      j[std::string(spec.name)] = values[0];
    } else {
      j[std::string(spec.name)] = json(std::vector<double>(values.begin(), values.end()));
    }
  }
  if (n.op == Op::mesh) j["mesh"] = n.source;
  if (n.op == Op::glsl) glsl_to_json(n.glsl->spec(), j, scene);
  if (n.material >= 0) j["material"] = scene.materials.at(static_cast<size_t>(n.material)).name;
  if (info.max_children == 1) {
    j["child"] = node_to_json(n.children[0], scene);
  } else if (info.max_children != 0) {
    json list = json::array();
    for (const auto& c : n.children) list.push_back(node_to_json(c, scene));
    j["children"] = list;
  }
  return j;
}

// A file named relative to the scene file (a mesh, a GLSL source, a texture) is found beside it.
std::string beside_scene_file(const std::string& file, const std::string& scene_path) {
  const std::filesystem::path p(file);
  if (p.is_absolute()) return file;
  // absolute() first: a bare "scene.json" has no parent path, and absolute("") is an error.
  return (std::filesystem::absolute(scene_path).parent_path() / p).lexically_normal().string();
}

std::string resolve_mesh_source(const std::string& source, const std::string& scene_path) {
  return source.starts_with("procedural:") ? source : beside_scene_file(source, scene_path);
}

// A glsl node's field: its source file (beside the scene file) or inline code, compiled here.
std::shared_ptr<const GlslField> glsl_from_json(const json& j, const std::string& path, const Scene& scene,
                                                const std::string& scene_path, std::vector<std::string>& allowed) {
  for (const char* key : {"source", "code", "function", "uniforms", "kind", "lipschitz", "precision", "materials"})
    allowed.push_back(key);
  GlslSpec spec;
  if (j.contains("source") == j.contains("code"))
    fail(path, "a glsl node needs \"source\" (a GLSL file) or \"code\" (the GLSL text), one of them");
  std::string text, file;
  if (j.contains("source")) {
    if (!j["source"].is_string() || j["source"].get<std::string>().empty()) fail(path + "/source", "expected a file path");
    spec.source = beside_scene_file(j["source"].get<std::string>(), scene_path);
    const std::optional<std::string> read = read_text_file(spec.source);
    if (!read) fail(path + "/source", "cannot read '" + spec.source + "'");
    text = *read;
    file = spec.source;
  } else {
    if (!j["code"].is_string()) fail(path + "/code", "expected the GLSL text as a string");
    text = spec.code = j["code"].get<std::string>();
    file = path + "/code";
  }
  if (j.contains("function")) {
    if (!j["function"].is_string() || j["function"].get<std::string>().empty())
      fail(path + "/function", "expected the name of the field's function");
    spec.function = j["function"].get<std::string>();
  }
  if (j.contains("uniforms")) {
    if (!j["uniforms"].is_object()) fail(path + "/uniforms", "expected an object of uniform names and values");
    for (const auto& [name, value] : j["uniforms"].items()) {
      const std::string where = path + "/uniforms/" + name;
      std::vector<double>& v = spec.uniforms[name];
      if (value.is_array()) {
        for (size_t i = 0; i < value.size(); ++i) v.push_back(number(value[i], where + "/" + std::to_string(i)));
      } else {
        v.push_back(number(value, where));
      }
    }
  }
  if (j.contains("precision")) {
    if (!j["precision"].is_string() || (j["precision"] != "float" && j["precision"] != "half"))
      fail(path + "/precision", "expected float or half (GLSL's mediump, in IEEE binary16)");
    spec.half = j["precision"] == "half";
  }
  if (j.contains("materials")) {
    if (!j["materials"].is_array()) fail(path + "/materials", "expected the names of the materials .y = 0, 1, ... selects");
    for (size_t i = 0; i < j["materials"].size(); ++i) {
      const std::string where = path + "/materials/" + std::to_string(i);
      const json& name = j["materials"][i];
      const int m = name.is_string() ? find_material(scene, name.get<std::string>()) : -1;
      if (m < 0) fail(where, "expected the name of one of the scene's materials");
      spec.materials.push_back(m);
    }
  }
  const std::string kind = j.contains("kind") && j["kind"].is_string() ? j["kind"].get<std::string>()
                           : j.contains("lipschitz")                   ? "lipschitz"
                                                                       : "unknown";
  if (j.contains("kind") && !j["kind"].is_string()) fail(path + "/kind", "expected exact, bound, lipschitz or unknown");
  spec.measured = kind == "unknown";
  if (kind == "exact") spec.kind = Kind::exact;
  else if (kind == "bound") spec.kind = Kind::bound;
  else if (kind == "lipschitz") spec.kind = Kind::lipschitz;
  else if (kind != "unknown") fail(path + "/kind", "expected exact, bound, lipschitz or unknown, got '" + kind + "'");
  if (kind == "lipschitz") {
    if (!j.contains("lipschitz")) fail(path, "a glsl node of kind lipschitz needs \"lipschitz\" (its constant)");
    spec.lipschitz = number(j["lipschitz"], path + "/lipschitz", 0, 1e300, true);
  } else if (j.contains("lipschitz")) {
    fail(path + "/lipschitz", "only a field of kind lipschitz states its constant");
  }
  try {
    return std::make_shared<const GlslField>(spec, text, file);
  } catch (const GlslError& e) {
    fail(path, e.what());
  }
}

// external: meshes and GLSL fields may be loaded and compiled (not for a fuzzer, which passes no mesh loader).
Node node_from_json(const json& j, const std::string& path, const Scene& scene, const std::string& scene_path,
                    bool external, int depth) {
  if (depth > kMaxTreeDepth) fail(path, "the tree nests deeper than " + std::to_string(kMaxTreeDepth) + " levels");
  if (!j.is_object()) fail(path, "expected an object with a \"type\"");
  // {"mesh": "file.obj"} is short for {"type": "mesh", "mesh": "file.obj"}.
  const bool mesh_shorthand = !j.contains("type") && j.contains("mesh");
  if (!mesh_shorthand && (!j.contains("type") || !j["type"].is_string()))
    fail(path, "missing \"type\" (a shape or operator name)");
  const std::string type = mesh_shorthand ? "mesh" : j["type"].get<std::string>();
  const OpInfo* info = find_op(type);
  if (!info) {
    std::string names;
    for (const Op op : all_ops()) names += std::string(names.empty() ? "" : ", ") + std::string(op_info(op).name);
    fail(path + "/type", "unknown type '" + type + "'; expected one of " + names);
  }
  Node n;
  n.op = info->op;
  std::vector<std::string> allowed = {"type", "material"};
  for (const auto& spec : info->params) {
    const std::string key(spec.name);
    allowed.push_back(key);
    const std::string where = path + "/" + key;
    if (!j.contains(key)) {
      if (spec.fallback.empty()) fail(path, type + " needs \"" + key + "\"");
      n.params.insert(n.params.end(), spec.fallback.begin(), spec.fallback.end());
      continue;
    }
    const json& v = j[key];
    if (spec.size == 1) {
      n.params.push_back(number(v, where, spec.min, spec.max));
      continue;
    }
    if (!v.is_array() || (spec.size > 0 && v.size() != static_cast<size_t>(spec.size)) ||
        (spec.size == 0 && (v.empty() || v.size() % 2 != 0)))
      fail(where, spec.size > 0 ? "expected an array of " + std::to_string(spec.size) + " numbers"
                                : "expected a non-empty array of number pairs");
    for (size_t i = 0; i < v.size(); ++i) n.params.push_back(number(v[i], where + "/" + std::to_string(i), spec.min, spec.max));
  }
  if (n.op == Op::mesh) {
    allowed.push_back("mesh");
    if (!j.contains("mesh") || !j["mesh"].is_string() || j["mesh"].get<std::string>().empty())
      fail(path + "/mesh", "expected a mesh file path or a procedural:NAME(ARGS) source");
    n.source = resolve_mesh_source(j["mesh"].get<std::string>(), scene_path);
  }
  if (n.op == Op::glsl) {
    if (!external) fail(path, "a GLSL field is not compiled here (no loader: meshes and GLSL are off)");
    n.glsl = glsl_from_json(j, path, scene, scene_path, allowed);
  }
  if (j.contains("material")) {
    if (!j["material"].is_string()) fail(path + "/material", "expected a material name");
    n.material = find_material(scene, j["material"].get<std::string>());
    if (n.material < 0) fail(path + "/material", "no material named '" + j["material"].get<std::string>() + "'");
  }
  if (info->max_children == 1) {
    allowed.push_back("child");
    if (!j.contains("child")) fail(path, type + " needs \"child\"");
    n.children.push_back(node_from_json(j["child"], path + "/child", scene, scene_path, external, depth + 1));
  } else if (info->max_children != 0) {
    allowed.push_back("children");
    if (!j.contains("children") || !j["children"].is_array()) fail(path, type + " needs \"children\" (an array)");
    const json& list = j["children"];
    for (size_t i = 0; i < list.size(); ++i)
      n.children.push_back(
          node_from_json(list[i], path + "/children/" + std::to_string(i), scene, scene_path, external, depth + 1));
  }
  for (const auto& [key, value] : j.items()) {
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string expected;
      for (const auto& a : allowed) expected += std::string(expected.empty() ? "" : ", ") + a;
      fail(path + "/" + key, "unknown key for " + type + "; expected one of " + expected);
    }
  }
  return n;
}

void check_keys(const json& j, const std::string& path, const std::vector<std::string>& allowed) {
  if (!j.is_object()) fail(path, "expected an object");
  for (const auto& [key, value] : j.items())
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string expected;
      for (const auto& a : allowed) expected += std::string(expected.empty() ? "" : ", ") + a;
      fail(path + "/" + key, "unknown key; expected one of " + expected);
    }
}

void read_section(Scene& scene, const json& j, const std::string& name) {
  const auto keys = section(name);
  std::vector<std::string> allowed;
  for (const auto* s : keys) allowed.push_back(s->key.substr(name.empty() ? 0 : name.size() + 1));
  check_keys(j, "/" + name, allowed);
  for (const auto* s : keys) {
    const std::string short_key = s->key.substr(name.empty() ? 0 : name.size() + 1);
    if (j.contains(short_key)) s->set(scene, j[short_key], "/" + name + "/" + short_key);
  }
}

json write_section(const Scene& scene, const std::string& name) {
  json j = json::object();
  for (const auto* s : section(name)) j[s->key.substr(name.size() + 1)] = s->get(scene);
  return j;
}

std::pair<int, int> line_column(std::string_view text, size_t byte) {
  int line = 1, column = 1;
  for (size_t i = 0; i < std::min(byte, text.size()); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {line, column};
}

// Where the parser gave up on a number too large for a double, and its text: a second pass that only listens.
std::pair<size_t, std::string> overflow_place(std::string_view text) {
  struct Listener : nlohmann::json_sax<json> {
    size_t byte = 0;
    std::string token;
    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override { return true; }
    bool key(string_t&) override { return true; }
    bool end_object() override { return true; }
    bool start_array(std::size_t) override { return true; }
    bool end_array() override { return true; }
    bool parse_error(std::size_t position, const std::string& last_token, const nlohmann::detail::exception&) override {
      byte = position >= last_token.size() ? position - last_token.size() : 0;
      token = last_token;
      return false;
    }
  } listener;
  json::sax_parse(text.begin(), text.end(), &listener);
  return {listener.byte, listener.token};
}

}  // namespace

std::vector<std::string> declared_effects(const Scene& scene) {
  std::vector<std::string> out;
  auto add = [&](const std::string& e) {
    if (std::find(out.begin(), out.end(), e) == out.end()) out.push_back(e);
  };
  const auto& effects = scene.effects;
  if (!scene.lights.empty()) add(effects.shading == Shading::toon ? "toon" : "diffuse:" + enum_name(kDiffuse, effects.diffuse));
  for (const auto& l : scene.lights) {
    if (l.shadow != ShadowMode::none) add("shadow:" + enum_name(kShadows, l.shadow) + "/" + enum_name(kBiases, l.bias));
    if (l.motion_rate != glm::dvec3(0)) add("moving-light");
  }
  for (const auto& m : scene.materials) {
    if (m.specular != SpecularModel::none) add("specular:" + enum_name(kSpeculars, m.specular));
    if (m.texture != TextureMapping::none) add("texture:" + enum_name(kTextures, m.texture));
    if (m.reflectivity > 0 && effects.max_bounces > 0) add("reflection");
    if (m.transparency > 0 && effects.max_bounces > 0) add("refraction");
    if (ramp_color(scene, m)) add("ramp");
  }
  if (effects.ao != AmbientOcclusion::none) add("ao:" + enum_name(kAo, effects.ao));
  if (!scene.meshes.empty()) add("mesh-occlusion");
  if (effects.glow > 0) add("glow");
  if (effects.fog > 0) add("fog");
  if (scene.camera.model == CameraModel::intrinsics &&
      (scene.camera.k1 != 0 || scene.camera.k2 != 0 || scene.camera.p1 != 0 || scene.camera.p2 != 0))
    add("lens-distortion");
  return out;
}

Scene scaled_to_width(const Scene& scene, int width) {
  Scene small = scene;
  const double k = static_cast<double>(width) / scene.width;
  small.width = std::max(1, width);
  small.height = std::max(1, static_cast<int>(scene.height * k));
  small.camera.fx *= k;
  small.camera.fy *= k;
  if (small.camera.cx >= 0) small.camera.cx *= k;
  if (small.camera.cy >= 0) small.camera.cy *= k;
  return small;
}

Scene moved_by(const Scene& scene, glm::dvec3 offset) {
  Scene out = scene;
  out.root = translate(offset, scene.root);
  if (scene.intended) out.intended = translate(offset, *scene.intended);
  for (auto& mesh : out.meshes)
    for (auto& v : mesh.vertices) v += offset;
  out.camera.position += offset;
  out.camera.target += offset;
  for (auto& light : out.lights) light.position += offset;  // a directional light's position is unused
  for (auto& m : out.materials) m.texture_origin += offset;
  return out;
}

std::optional<glm::dvec3> ramp_color(const Scene& scene, const Material& material) {
  const auto& ramp = scene.effects.ramp;
  if (material.ramp_value < 0 || ramp.empty()) return std::nullopt;
  const double x = material.ramp_value * static_cast<double>(ramp.size() - 1);
  const size_t i = std::min(static_cast<size_t>(x), ramp.size() - 1), j = std::min(i + 1, ramp.size() - 1);
  return glm::mix(ramp[i], ramp[j], x - static_cast<double>(i));
}

int find_material(const Scene& scene, std::string_view name) {
  for (size_t i = 0; i < scene.materials.size(); ++i)
    if (scene.materials[i].name == name) return static_cast<int>(i);
  return -1;
}

namespace {

const Field<Scene>& known_setting(std::string_view key) {
  const Field<Scene>* s = find_setting(key);
  if (!s) {
    std::string names;
    for (const auto& k : settings()) names += std::string(names.empty() ? "" : ", ") + k.key;
    throw SceneError(std::string(key) + ": unknown key; expected one of " + names);
  }
  return *s;
}

}  // namespace

void apply_setting(Scene& scene, std::string_view key, std::string_view value) {
  known_setting(key).set(scene, parse_setting_value(value), std::string(key) + "=" + std::string(value));
}

std::string setting_text(const Scene& scene, std::string_view key) {
  const Field<Scene>& s = known_setting(key);
  if (!s.get) throw SceneError(std::string(key) + ": a setting of every light, with no one value to read");
  const json v = s.get(scene);
  return v.is_string() ? v.get<std::string>() : v.dump();
}

std::string scene_to_json(const Scene& scene) {
  json j;
  j["name"] = scene.name;
  j["description"] = scene.description;
  if (!scene.defects.empty()) j["defects"] = scene.defects;
  for (const auto* s : section("")) j[s->key] = s->get(scene);
  j["camera"] = write_section(scene, "camera");
  j["effects"] = write_section(scene, "effects");
  json materials = json::array();
  for (const auto& m : scene.materials) materials.push_back(write_fields(m, material_fields()));
  j["materials"] = materials;
  json lights = json::array();
  for (const auto& l : scene.lights) lights.push_back(write_fields(l, light_fields()));
  j["lights"] = lights;
  if (!scene.meshes.empty()) {
    json meshes = json::array();
    for (const auto& m : scene.meshes) {
      json vertices = json::array(), triangles = json::array();
      for (const auto& v : m.vertices) vertices.push_back(vec3_json(v));
      for (const auto& t : m.triangles) triangles.push_back({t[0], t[1], t[2]});
      json mj = {{"name", m.name}, {"vertices", vertices}, {"triangles", triangles}};
      if (m.material >= 0) mj["material"] = scene.materials.at(static_cast<size_t>(m.material)).name;
      meshes.push_back(mj);
    }
    j["meshes"] = meshes;
  }
  j["limits"] = scene.limits;
  j["sdf"] = node_to_json(scene.root, scene);
  if (scene.intended) j["intended_sdf"] = node_to_json(*scene.intended, scene);
  return j.dump(2) + "\n";
}

namespace {

void load_node_meshes(Node& n, const MeshLoader& loader, const std::string& path,
                      std::map<std::string, std::shared_ptr<const MeshDistance>>& loaded) {
  if (n.op == Op::mesh && !n.mesh) {
    const double weld = n.scalar("weld");
    // One distance structure per file and weld (the weld's exact bits: to_string would round 1e-9 to 0).
    auto& shared = loaded[n.source + "\n" + std::to_string(std::bit_cast<std::uint64_t>(weld))];
    if (!shared) {
      if (!loader)
        fail(path + "/mesh", "'" + n.source + "': no mesh loader to read it with (meshes are off here)");
      try {
        meshes::Mesh mesh = loader(n.source);
        std::string note;
        if (weld > 0) note = "mesh '" + n.source + "' " + meshes::describe(meshes::weld(mesh, weld), weld);
        shared = std::make_shared<const MeshDistance>(mesh, std::move(note));
      } catch (const std::exception& e) {
        const std::string what = e.what();
        // Loaders' errors name the file already; the mesh checks' errors do not.
        fail(path + "/mesh", what.find(n.source) != std::string::npos ? what : "'" + n.source + "': " + what);
      }
    }
    n.mesh = shared;
  }
  const int max_children = op_info(n.op).max_children;
  for (size_t i = 0; i < n.children.size(); ++i)
    load_node_meshes(n.children[i], loader, path + (max_children == 1 ? "/child" : "/children/" + std::to_string(i)),
                     loaded);
}

}  // namespace

std::vector<std::string> mesh_notes(const Node& root) {
  std::vector<std::string> notes;
  const auto visit = [&](const auto& self, const Node& n) -> void {
    if (n.mesh && !n.mesh->note().empty() &&
        std::find(notes.begin(), notes.end(), n.mesh->note()) == notes.end())
      notes.push_back(n.mesh->note());
    for (const Node& c : n.children) self(self, c);
  };
  visit(visit, root);
  return notes;
}

void load_meshes(Scene& scene, const MeshLoader& loader) {
  std::map<std::string, std::shared_ptr<const MeshDistance>> loaded;
  load_node_meshes(scene.root, loader, "/sdf", loaded);
  if (scene.intended) load_node_meshes(*scene.intended, loader, "/intended_sdf", loaded);
}

Scene scene_from_json(std::string_view text, const std::string& source, const MeshLoader& loader) {
  json j;
  try {
    j = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    const auto [line, column] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    if (const auto pos = what.find("syntax error"); pos != std::string::npos) what = what.substr(pos);
    throw SceneError(source + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + what);
  } catch (const json::out_of_range&) {
    // A number beyond the double range (fuzz_scene found "1e3080"); the exception carries no position.
    const auto [byte, token] = overflow_place(text);
    const auto [line, column] = line_column(text, byte);
    throw SceneError(source + ":" + std::to_string(line) + ":" + std::to_string(column) + ": the number " +
                     token.substr(0, 40) + " is beyond the range of a double");
  }
  try {
    Scene scene;
    std::vector<std::string> allowed = {"name",   "description", "defects", "camera", "materials", "lights",
                                        "meshes", "effects",     "limits",  "sdf",    "intended_sdf"};
    for (const auto* s : section("")) allowed.push_back(s->key);
    check_keys(j, "", allowed);
    for (const char* key : {"name", "description"})
      if (j.contains(key)) {
        if (!j[key].is_string()) fail(std::string("/") + key, "expected a string");
        (std::string_view(key) == "name" ? scene.name : scene.description) = j[key].get<std::string>();
      }
    if (j.contains("defects")) {
      if (!j["defects"].is_array()) fail("/defects", "expected an array of names");
      for (size_t i = 0; i < j["defects"].size(); ++i) {
        if (!j["defects"][i].is_string()) fail("/defects/" + std::to_string(i), "expected a string");
        scene.defects.push_back(j["defects"][i].get<std::string>());
      }
    }
    for (const auto* s : section(""))  // precision after the tree: half is its GLSL fields'
      if (j.contains(s->key) && s->key != "precision") s->set(scene, j[s->key], "/" + s->key);
    if (j.contains("camera")) read_section(scene, j["camera"], "camera");
    if (j.contains("effects")) read_section(scene, j["effects"], "effects");
    if (j.contains("materials")) {
      if (!j["materials"].is_array()) fail("/materials", "expected an array");
      for (size_t i = 0; i < j["materials"].size(); ++i) {
        const std::string where = "/materials/" + std::to_string(i);
        Material mat;
        read_fields(mat, j["materials"][i], material_fields(), where);
        if (mat.name.empty()) fail(where, "needs a \"name\"");
        if (!mat.texture_file.empty()) {
          if (mat.texture == TextureMapping::none)
            fail(where + "/texture_file", "an image needs a \"texture\" mapping (planar or spherical)");
          mat.texture_file = beside_scene_file(mat.texture_file, source);
          if (!std::filesystem::is_regular_file(mat.texture_file))
            fail(where + "/texture_file", "'" + mat.texture_file + "': no such file");
        }
        if (find_material(scene, mat.name) >= 0) fail(where + "/name", "duplicate material '" + mat.name + "'");
        scene.materials.push_back(mat);
      }
    }
    if (j.contains("lights")) {
      if (!j["lights"].is_array()) fail("/lights", "expected an array");
      for (size_t i = 0; i < j["lights"].size(); ++i) {
        const std::string where = "/lights/" + std::to_string(i);
        Light light;
        read_fields(light, j["lights"][i], light_fields(), where);
        if (light.type == LightType::directional && glm::length(light.direction) == 0)
          fail(where + "/direction", "must not be zero");
        scene.lights.push_back(light);
      }
    }
    if (j.contains("meshes")) {
      if (!j["meshes"].is_array()) fail("/meshes", "expected an array");
      for (size_t i = 0; i < j["meshes"].size(); ++i) {
        const json& mj = j["meshes"][i];
        const std::string where = "/meshes/" + std::to_string(i);
        check_keys(mj, where, {"name", "vertices", "triangles", "material"});
        SceneMesh mesh;
        if (mj.contains("name")) {
          if (!mj["name"].is_string()) fail(where + "/name", "expected a string");
          mesh.name = mj["name"].get<std::string>();
        }
        if (!mj.contains("vertices") || !mj["vertices"].is_array()) fail(where, "needs \"vertices\" (an array of [x, y, z])");
        if (!mj.contains("triangles") || !mj["triangles"].is_array()) fail(where, "needs \"triangles\" (an array of [i, j, k])");
        for (size_t v = 0; v < mj["vertices"].size(); ++v)
          mesh.vertices.push_back(vec3(mj["vertices"][v], where + "/vertices/" + std::to_string(v)));
        for (size_t t = 0; t < mj["triangles"].size(); ++t) {
          const std::string tw = where + "/triangles/" + std::to_string(t);
          const json& tri = mj["triangles"][t];
          if (!tri.is_array() || tri.size() != 3) fail(tw, "expected 3 vertex indices");
          const int hi = static_cast<int>(mesh.vertices.size()) - 1;
          mesh.triangles.push_back({static_cast<std::uint32_t>(integer(tri[0], tw + "/0", 0, hi)),
                                    static_cast<std::uint32_t>(integer(tri[1], tw + "/1", 0, hi)),
                                    static_cast<std::uint32_t>(integer(tri[2], tw + "/2", 0, hi))});
        }
        if (mesh.triangles.empty()) fail(where, "needs at least one triangle");
        if (mj.contains("material")) {
          if (!mj["material"].is_string()) fail(where + "/material", "expected a material name");
          mesh.material = find_material(scene, mj["material"].get<std::string>());
          if (mesh.material < 0) fail(where + "/material", "no material named '" + mj["material"].get<std::string>() + "'");
        }
        scene.meshes.push_back(std::move(mesh));
      }
    }
    if (j.contains("limits")) {
      if (!j["limits"].is_object()) fail("/limits", "expected an object of metric names to numbers");
      for (const auto& [key, value] : j["limits"].items()) scene.limits[key] = number(value, "/limits/" + key);
    }
    if (!j.contains("sdf")) fail("", "missing \"sdf\" (the scene's shape tree)");
    const bool external = static_cast<bool>(loader);
    scene.root = node_from_json(j["sdf"], "/sdf", scene, source, external, 0);
    if (j.contains("intended_sdf"))
      scene.intended = node_from_json(j["intended_sdf"], "/intended_sdf", scene, source, external, 0);
    if (j.contains("precision")) {
      set_precision(scene, j["precision"], "/precision");
    } else {  // a GLSL node's mediump is the scene's precision
      each_glsl_field(scene.root, [&](const auto& field) {
        if (field->spec().half) scene.march.precision = Precision::float16;
      });
    }
    load_meshes(scene, loader);
    if (auto error = validate_tree(scene.root); !error.empty()) throw SceneError("/sdf" + error);
    if (scene.intended)
      if (auto error = validate_tree(*scene.intended); !error.empty()) throw SceneError("/intended_sdf" + error);
    return scene;
  } catch (const SceneError& e) {
    throw SceneError(source + ": " + e.what());
  }
}

std::optional<std::string> read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Scene load_scene_file(const std::string& path, const MeshLoader& loader) {
  const std::optional<std::string> text = read_text_file(path);
  if (!text) throw SceneError(path + ": cannot open the scene file");
  Scene scene = scene_from_json(*text, path, loader);
  // Output, result files and the report name scenes: one without a name goes by its file's.
  if (scene.name.empty()) scene.name = std::filesystem::path(path).stem().string();
  return scene;
}

}  // namespace marchcheck::sdf
