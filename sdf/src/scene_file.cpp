#include "marchcheck/sdf/scene_file.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
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
constexpr EnumName<EpsMode> kEpsModes[] = {
    {EpsMode::absolute, "absolute"}, {EpsMode::relative, "relative"}, {EpsMode::pixel, "pixel"}};
constexpr EnumName<NormalMethod> kNormals[] = {{NormalMethod::central, "central"},
                                               {NormalMethod::forward, "forward"},
                                               {NormalMethod::tetra, "tetra"},
                                               {NormalMethod::analytic, "analytic"}};
constexpr EnumName<ShadowMode> kShadows[] = {
    {ShadowMode::none, "none"}, {ShadowMode::hard, "hard"}, {ShadowMode::soft, "soft"}};
constexpr EnumName<Precision> kPrecisions[] = {{Precision::single, "float"}, {Precision::dual, "double"}};
constexpr EnumName<CameraModel> kCameraModels[] = {{CameraModel::pinhole, "pinhole"},
                                                   {CameraModel::intrinsics, "intrinsics"},
                                                   {CameraModel::frustum, "frustum"},
                                                   {CameraModel::orthographic, "orthographic"}};
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

double number(const json& v, const std::string& where, double lo = -1e300, double hi = 1e300) {
  if (!v.is_number()) fail(where, "expected a number, got " + std::string(v.type_name()));
  const double x = v.get<double>();
  if (!(x >= lo && x <= hi)) {
    std::ostringstream s;
    s << "value " << x << " is out of range [" << lo << ", " << hi << "]";
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

// One settable key: JSON section, getter and setter. Drives --set, the scene file's "march" and "camera"
// sections and their export, so the three never disagree.
struct Setting {
  std::string key;
  std::function<json(const Scene&)> get;
  std::function<void(Scene&, const json&, const std::string&)> set;
};

template <class E, size_t N, class M>
Setting enum_setting(std::string key, const EnumName<E> (&table)[N], M member) {
  return {key, [&table, member](const Scene& s) { return json(enum_name(table, member(const_cast<Scene&>(s)))); },
          [&table, member](Scene& s, const json& v, const std::string& w) { member(s) = enum_value(table, v, w); }};
}
template <class M>
Setting number_setting(std::string key, M member, double lo, double hi) {
  return {key, [member](const Scene& s) { return json(member(const_cast<Scene&>(s))); },
          [member, lo, hi](Scene& s, const json& v, const std::string& w) { member(s) = number(v, w, lo, hi); }};
}
template <class M>
Setting int_setting(std::string key, M member, int lo, int hi) {
  return {key, [member](const Scene& s) { return json(member(const_cast<Scene&>(s))); },
          [member, lo, hi](Scene& s, const json& v, const std::string& w) { member(s) = integer(v, w, lo, hi); }};
}
template <class M>
Setting vec3_setting(std::string key, M member) {
  return {key, [member](const Scene& s) { return vec3_json(member(const_cast<Scene&>(s))); },
          [member](Scene& s, const json& v, const std::string& w) { member(s) = vec3(v, w); }};
}

#define MEMBER(expr) [](Scene& s) -> auto& { return s.expr; }

const std::vector<Setting>& settings() {
  static const std::vector<Setting> table = {
      enum_setting("marcher", kMarchers, MEMBER(march.marcher)),
      int_setting("max_steps", MEMBER(march.max_steps), 0, 1 << 24),
      number_setting("max_dist", MEMBER(march.max_dist), 0, INFINITY),
      number_setting("hit_eps", MEMBER(march.hit_eps), 0, 1e6),
      enum_setting("eps_mode", kEpsModes, MEMBER(march.eps_mode)),
      number_setting("step_scale", MEMBER(march.step_scale), 1e-6, 2),
      number_setting("relaxation", MEMBER(march.relaxation), 1, 2),
      number_setting("fixed_step", MEMBER(march.fixed_step), 1e-9, 1e6),
      enum_setting("normal", kNormals, MEMBER(march.normal)),
      number_setting("normal_eps", MEMBER(march.normal_eps), 1e-12, 1),
      {"normal_eps_scaled", [](const Scene& s) { return json(s.march.normal_eps_scaled); },
       [](Scene& s, const json& v, const std::string& w) {
         if (!v.is_boolean()) fail(w, "expected true or false");
         s.march.normal_eps_scaled = v.get<bool>();
       }},
      enum_setting("shadow", kShadows, MEMBER(march.shadow)),
      number_setting("shadow_bias", MEMBER(march.shadow_bias), 0, 1e6),
      enum_setting("precision", kPrecisions, MEMBER(march.precision)),
      number_setting("time", MEMBER(time), -1e6, 1e6),
      int_setting("width", MEMBER(width), 1, 16384),
      int_setting("height", MEMBER(height), 1, 16384),
      enum_setting("camera.model", kCameraModels, MEMBER(camera.model)),
      enum_setting("camera.pose", kCameraPoses, MEMBER(camera.pose)),
      vec3_setting("camera.position", MEMBER(camera.position)),
      vec3_setting("camera.target", MEMBER(camera.target)),
      vec3_setting("camera.up", MEMBER(camera.up)),
      number_setting("camera.yaw_deg", MEMBER(camera.yaw_deg), -1e6, 1e6),
      number_setting("camera.pitch_deg", MEMBER(camera.pitch_deg), -89.9, 89.9),
      number_setting("camera.distance", MEMBER(camera.distance), 1e-9, 1e12),
      number_setting("camera.fov_deg", MEMBER(camera.fov_deg), 1e-3, 179),
      number_setting("camera.fx", MEMBER(camera.fx), 1e-6, 1e9),
      number_setting("camera.fy", MEMBER(camera.fy), 1e-6, 1e9),
      number_setting("camera.cx", MEMBER(camera.cx), -1, 1e9),
      number_setting("camera.cy", MEMBER(camera.cy), -1, 1e9),
      number_setting("camera.k1", MEMBER(camera.k1), -10, 10),
      number_setting("camera.k2", MEMBER(camera.k2), -10, 10),
      number_setting("camera.p1", MEMBER(camera.p1), -10, 10),
      number_setting("camera.p2", MEMBER(camera.p2), -10, 10),
      number_setting("camera.ortho_height", MEMBER(camera.ortho_height), 1e-12, 1e12),
      vec3_setting("effects.background", MEMBER(effects.background)),
      number_setting("effects.ambient", MEMBER(effects.ambient), 0, 1),
  };
  return table;
}

#undef MEMBER

const Setting* find_setting(std::string_view key) {
  for (const auto& s : settings())
    if (s.key == key) return &s;
  return nullptr;
}

// The settings of one section ("" = top level keys without a dot).
std::vector<const Setting*> section(std::string_view prefix) {
  std::vector<const Setting*> out;
  for (const auto& s : settings()) {
    const auto dot = s.key.find('.');
    const std::string_view head = dot == std::string::npos ? "" : std::string_view(s.key).substr(0, dot);
    if (head == prefix) out.push_back(&s);
  }
  return out;
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

Node node_from_json(const json& j, const std::string& path, const Scene& scene, int depth) {
  if (depth > kMaxTreeDepth) fail(path, "the tree nests deeper than " + std::to_string(kMaxTreeDepth) + " levels");
  if (!j.is_object()) fail(path, "expected an object with a \"type\"");
  if (!j.contains("type") || !j["type"].is_string()) fail(path, "missing \"type\" (a shape or operator name)");
  const std::string type = j["type"].get<std::string>();
  const OpInfo* info = find_op(type);
  if (!info) {
    std::string names;
    for (const auto& op : all_ops()) names += std::string(names.empty() ? "" : ", ") + std::string(op.name);
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
  if (j.contains("material")) {
    if (!j["material"].is_string()) fail(path + "/material", "expected a material name");
    n.material = find_material(scene, j["material"].get<std::string>());
    if (n.material < 0) fail(path + "/material", "no material named '" + j["material"].get<std::string>() + "'");
  }
  if (info->max_children == 1) {
    allowed.push_back("child");
    if (!j.contains("child")) fail(path, type + " needs \"child\"");
    n.children.push_back(node_from_json(j["child"], path + "/child", scene, depth + 1));
  } else if (info->max_children != 0) {
    allowed.push_back("children");
    if (!j.contains("children") || !j["children"].is_array()) fail(path, type + " needs \"children\" (an array)");
    const json& list = j["children"];
    for (size_t i = 0; i < list.size(); ++i)
      n.children.push_back(node_from_json(list[i], path + "/children/" + std::to_string(i), scene, depth + 1));
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

}  // namespace

int find_material(const Scene& scene, std::string_view name) {
  for (size_t i = 0; i < scene.materials.size(); ++i)
    if (scene.materials[i].name == name) return static_cast<int>(i);
  return -1;
}

void apply_setting(Scene& scene, std::string_view key, std::string_view value) {
  const Setting* s = find_setting(key);
  if (!s) {
    std::string names;
    for (const auto& k : settings()) names += std::string(names.empty() ? "" : ", ") + k.key;
    throw SceneError("--set " + std::string(key) + ": unknown key; expected one of " + names);
  }
  s->set(scene, parse_setting_value(value), "--set " + std::string(key) + "=" + std::string(value));
}

std::vector<std::string> setting_keys() {
  std::vector<std::string> keys;
  for (const auto& s : settings()) keys.push_back(s.key);
  return keys;
}

std::string scene_to_json(const Scene& scene) {
  json j;
  j["name"] = scene.name;
  j["description"] = scene.description;
  for (const auto* s : section("")) j[s->key] = s->get(scene);
  j["camera"] = write_section(scene, "camera");
  json materials = json::array();
  for (const auto& m : scene.materials) materials.push_back({{"name", m.name}, {"color", vec3_json(m.color)}});
  j["materials"] = materials;
  json lights = json::array();
  for (const auto& l : scene.lights) {
    json lj = {{"type", enum_name(kLightTypes, l.type)}, {"color", vec3_json(l.color)}};
    if (l.type == LightType::point) {
      lj["position"] = vec3_json(l.position);
    } else {
      lj["direction"] = vec3_json(l.direction);
    }
    lights.push_back(lj);
  }
  j["lights"] = lights;
  j["effects"] = write_section(scene, "effects");
  j["limits"] = scene.limits;
  j["sdf"] = node_to_json(scene.root, scene);
  return j.dump(2) + "\n";
}

Scene scene_from_json(std::string_view text, const std::string& source) {
  json j;
  try {
    j = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    const auto [line, column] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    if (const auto pos = what.find("syntax error"); pos != std::string::npos) what = what.substr(pos);
    throw SceneError(source + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + what);
  }
  try {
    Scene scene;
    std::vector<std::string> allowed = {"name", "description", "camera", "materials", "lights",
                                        "effects", "limits", "sdf"};
    for (const auto* s : section("")) allowed.push_back(s->key);
    check_keys(j, "", allowed);
    if (j.contains("name")) {
      if (!j["name"].is_string()) fail("/name", "expected a string");
      scene.name = j["name"].get<std::string>();
    }
    if (j.contains("description")) {
      if (!j["description"].is_string()) fail("/description", "expected a string");
      scene.description = j["description"].get<std::string>();
    }
    for (const auto* s : section(""))
      if (j.contains(s->key)) s->set(scene, j[s->key], "/" + s->key);
    if (j.contains("camera")) read_section(scene, j["camera"], "camera");
    if (j.contains("effects")) read_section(scene, j["effects"], "effects");
    if (j.contains("materials")) {
      if (!j["materials"].is_array()) fail("/materials", "expected an array");
      for (size_t i = 0; i < j["materials"].size(); ++i) {
        const json& m = j["materials"][i];
        const std::string where = "/materials/" + std::to_string(i);
        check_keys(m, where, {"name", "color"});
        if (!m.contains("name") || !m["name"].is_string()) fail(where, "needs a \"name\" (a string)");
        Material mat;
        mat.name = m["name"].get<std::string>();
        if (find_material(scene, mat.name) >= 0) fail(where + "/name", "duplicate material '" + mat.name + "'");
        if (m.contains("color")) mat.color = vec3(m["color"], where + "/color");
        scene.materials.push_back(mat);
      }
    }
    if (j.contains("lights")) {
      if (!j["lights"].is_array()) fail("/lights", "expected an array");
      for (size_t i = 0; i < j["lights"].size(); ++i) {
        const json& l = j["lights"][i];
        const std::string where = "/lights/" + std::to_string(i);
        check_keys(l, where, {"type", "position", "direction", "color"});
        Light light;
        if (!l.contains("type")) fail(where, "needs a \"type\" (point or directional)");
        light.type = enum_value(kLightTypes, l["type"], where + "/type");
        if (light.type == LightType::point) {
          if (!l.contains("position")) fail(where, "a point light needs \"position\"");
          light.position = vec3(l["position"], where + "/position");
        } else {
          if (!l.contains("direction")) fail(where, "a directional light needs \"direction\"");
          light.direction = vec3(l["direction"], where + "/direction");
          if (glm::length(light.direction) == 0) fail(where + "/direction", "must not be zero");
        }
        if (l.contains("color")) light.color = vec3(l["color"], where + "/color");
        scene.lights.push_back(light);
      }
    }
    if (j.contains("limits")) {
      if (!j["limits"].is_object()) fail("/limits", "expected an object of metric names to numbers");
      for (const auto& [key, value] : j["limits"].items()) scene.limits[key] = number(value, "/limits/" + key);
    }
    if (!j.contains("sdf")) fail("", "missing \"sdf\" (the scene's shape tree)");
    scene.root = node_from_json(j["sdf"], "/sdf", scene, 0);
    if (auto error = validate_tree(scene.root); !error.empty()) throw SceneError("/sdf" + error);
    return scene;
  } catch (const SceneError& e) {
    throw SceneError(source + ": " + e.what());
  }
}

Scene load_scene_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return scene_from_json(text.str(), path);
}

}  // namespace marchcheck::sdf
