#include "marchcheck/sdf/builtin_scenes.hpp"

#include "marchcheck/sdf/scene_file.hpp"

#include <cmath>
#include <functional>
#include <utility>

namespace marchcheck::sdf {

namespace {

int add_material(Scene& s, std::string name, glm::dvec3 color) {
  s.materials.push_back({std::move(name), color});
  return static_cast<int>(s.materials.size() - 1);
}

Light point_light(glm::dvec3 position, glm::dvec3 color) {
  Light l;
  l.type = LightType::point;
  l.position = position;
  l.color = color;
  return l;
}

Light directional_light(glm::dvec3 direction, glm::dvec3 color) {
  Light l;
  l.type = LightType::directional;
  l.direction = direction;
  l.color = color;
  return l;
}

void look_at(Scene& s, glm::dvec3 position, glm::dvec3 target, double fov_deg) {
  s.camera.model = CameraModel::pinhole;
  s.camera.pose = CameraPose::look_at;
  s.camera.position = position;
  s.camera.target = target;
  s.camera.fov_deg = fov_deg;
}

Scene base(std::string name, std::string description) {
  Scene s;
  s.name = std::move(name);
  s.description = std::move(description);
  s.width = 1280;
  s.height = 720;
  return s;
}

// lee: sphere (0, 1.2, 0) r 1 over the ground; orbit camera, f = 600 px intrinsics, k1 = 0.3.
Scene lee(bool terrain) {
  Scene s = base(terrain ? "lee-terrain" : "lee-flat",
                 terrain ? "Sphere over a value-noise height-field terrain (SDF y + height(x,z)), marched at f/L"
                         : "Sphere over a ground plane, orbit camera with lens distortion, hard shadows");
  const int ball = add_material(s, "sphere", {0.5, 0.7, 1.0});
  const int ground = add_material(s, "ground", {0.57, 0.42, 0.3});
  Node floor = terrain ? make(Op::heightfield, {{"octaves", {-0.5, 0.5, -0.05, 2, -0.012, 4}}}, {}, ground)
                       : plane({0, 1, 0}, 0, ground);
  s.root = unite({translate({0, 1.2, 0}, sphere(1, ball)), std::move(floor)});
  s.camera.model = CameraModel::intrinsics;
  s.camera.pose = CameraPose::orbit;
  s.camera.distance = 6;
  s.camera.yaw_deg = 0;
  s.camera.pitch_deg = 0.3 * 180 / M_PI;
  s.camera.fx = s.camera.fy = 600;
  s.camera.k1 = 0.3;
  s.lights = {point_light({0, 5, 6}, {1, 1, 1})};
  s.march.max_steps = 200;
  s.march.max_dist = 100;
  s.march.hit_eps = 0.01;
  s.march.normal_eps = 0.01;
  s.effects.background = {0, 0, 0};
  if (terrain) s.march.marcher = Marcher::scaled;  // the height field's Lipschitz bound is above 1
  return s;
}

void crum_common(Scene& s) {
  look_at(s, {-2, 4, 4}, {0, 0, 0}, 70);
  s.march.max_steps = 255;
  s.march.max_dist = 700;
  s.march.hit_eps = 1e-4;
  s.march.normal_eps = 1e-4;
  s.lights = {point_light({2, 2, 2}, {1.5, 0, 0}), point_light({-2, 2, 2}, {0, 1.5, 0}),
              point_light({2, 2, -2}, {0, 0, 1.5}), point_light({-2, -2, -2}, {1.5, 1.5, 1.5})};
  s.effects.ambient = 0.1;
  s.march.shadow = ShadowMode::none;
}

Scene crum_torus() {
  Scene s = base("crum-torus", "Torus (1.0, 0.3) in the xz plane under four coloured point lights");
  const int m = add_material(s, "torus", {1, 1, 1});
  s.root = torus(1.0, 0.3, m);
  crum_common(s);
  return s;
}

Scene crum_smooth() {
  Scene s = base("crum-smooth", "Sphere, box and torus joined by the polynomial smooth union, k = 0.5");
  const int m = add_material(s, "blend", {1, 1, 1});
  s.root = smooth_union(0.5, {sphere(0.2), translate({0.6, 0, 0}, box(glm::dvec3(0.3))),
                              translate({-0.7, 0, 0}, torus(0.3, 0.1))});
  s.root.material = m;
  crum_common(s);
  look_at(s, {-0.8, 1.6, 1.6}, {0, 0, 0}, 70);
  return s;
}

Scene crum_lattice() {
  Scene s = base("crum-lattice", "Box frames repeated every 10 units, displaced by 0.1 sin(15x) sin(15y) sin(15z)");
  const int m = add_material(s, "frame", {1, 1, 1});
  Node frame = make(Op::box_frame, {{"half_size", {5, 5, 5}}, {"thickness", {0.2}}}, {}, m);
  Node lattice = make(Op::repeat, {{"period", {10, 10, 10}}}, {std::move(frame)});
  s.root = make(Op::displace, {{"amplitude", {0.1}}, {"frequency", {15}}}, {std::move(lattice)});
  crum_common(s);
  s.march.marcher = Marcher::scaled;  // displacement raises the Lipschitz bound to 2.5
  return s;
}

Scene crum_mandelbulb() {
  Scene s = base("crum-mandelbulb", "Power-8 Mandelbulb distance estimator, 8 iterations, bailout 2");
  const int m = add_material(s, "bulb", {1, 1, 1});
  s.root = make(Op::mandelbulb, {{"power", {8}}, {"iterations", {8}}, {"bailout", {2}}}, {}, m);
  crum_common(s);
  look_at(s, {-1.1, 1.5, 2.0}, {0, 0, 0}, 70);
  s.march.marcher = Marcher::scaled;
  s.march.hit_eps = 1e-4;
  return s;
}

Scene fogerty() {
  Scene s = base("fogerty", "Toon-shaded sphere of radius 3 seen from (0, 0, -10) with a 90 degree field of view");
  const int m = add_material(s, "toon", {1, 0, 0});
  s.root = sphere(3, m);
  look_at(s, {0, 0, -10}, {0, 0, 0}, 90);
  s.lights = {point_light({1.5, 4.5, -10}, {1, 1, 1})};
  s.march.max_steps = 256;
  s.march.hit_eps = 1e-4;
  s.march.max_dist = 10000;
  s.march.normal_eps = 1e-3;
  s.march.shadow = ShadowMode::none;
  s.effects.background = glm::dvec3(0.7);
  return s;
}

Scene warped() {
  Scene s = base("warped", "Sphere of radius 2 whose centre is displaced by time-varying sinusoids (time = 1)");
  const int m = add_material(s, "warped", {1, 1, 1});
  s.root = make(Op::warp, {}, {sphere(2, m)});
  s.time = 1;
  look_at(s, {0, 0, -1}, {0, 0, 1}, 90);
  s.lights = {directional_light({-1, -1, 1}, {1, 0.1, 0.1}), directional_light({1, -1, 1}, {0, 0.25, 0}),
              directional_light({0, 1, 1}, {0, 0, 0.25})};
  s.march.max_steps = 256;
  s.march.hit_eps = 0.02;
  s.march.max_dist = 100;
  s.march.normal = NormalMethod::forward;
  s.march.shadow = ShadowMode::none;
  s.march.marcher = Marcher::scaled;  // the warp's slope reaches 4: step by f / L
  return s;
}

// Unity's view space is left-handed; seen from +z in this right-handed one, +x is on the right as there.
void flafla_common(Scene& s, glm::dvec3 eye) {
  look_at(s, eye, {0, 0, 0}, 60);
  s.march.max_steps = 64;
  s.march.hit_eps = 0.001;
  s.march.max_dist = 40;
  s.march.normal_eps = 0.001;
  s.march.shadow = ShadowMode::none;
  s.lights = {directional_light({-0.3, -1, -0.5}, {1, 1, 1})};
}

Scene flafla_torus() {
  Scene s = base("flafla-torus", "Unity image-effect marcher: torus (1, 0.2), 64 steps, draw distance 40");
  const int m = add_material(s, "torus", {0.9, 0.9, 0.9});
  s.root = torus(1, 0.2, m);
  flafla_common(s, {0, 2, 4});
  return s;
}

Scene flafla_csg() {
  Scene s = base("flafla-csg", "Union, subtraction and intersection of unit boxes");
  const int m = add_material(s, "csg", {0.9, 0.9, 0.9});
  const glm::dvec3 unit(1);
  Node u = unite({translate({-4.5, 0.5, 0}, box(unit)), translate({-3.5, -0.5, 0}, box(unit))});
  Node d = subtract(translate({0.5, -0.5, 0}, box(unit)), translate({-0.5, 0.5, 0}, box({1, 1, 1.01})));
  Node i = intersect(translate({3.5, 0.5, 0}, box(unit)), translate({4.5, -0.5, 0}, box(unit)));
  s.root = unite({std::move(u), std::move(d), std::move(i)});
  s.root.material = m;
  flafla_common(s, {0, 4, 10});
  return s;
}

Scene flafla_materials() {
  Scene s = base("flafla-materials", "Torus, box and sphere whose material values 0.5, 0.25, 0.75 pick ramp colours");
  // The seed's ramp: blue at 0, green at 0.5, red at 1.
  const int torus_m = add_material(s, "ramp-0.5", {0.1, 0.9, 0.2});
  const int box_m = add_material(s, "ramp-0.25", {0.1, 0.5, 0.6});
  const int sphere_m = add_material(s, "ramp-0.75", {0.6, 0.5, 0.1});
  s.root = unite({torus(1, 0.2, torus_m), translate({-3, 0, 0}, box({0.75, 0.5, 0.5}, box_m)),
                  translate({3, 0, 0}, sphere(1, sphere_m))});
  flafla_common(s, {0, 3, 7});
  return s;
}

Scene flafla_animated() {
  Scene s = base("flafla-animated", "Torus under a model matrix: translate (5 sin t, 0, 0), rotate 200 t degrees about z");
  const int m = add_material(s, "torus", {0.9, 0.9, 0.9});
  s.root = make(Op::animate, {{"translate_sin", {5, 0, 0}}, {"spin_axis", {0, 0, 1}}, {"spin_deg_per_s", {200}}},
                {torus(1, 0.2, m)});
  s.time = 1;
  flafla_common(s, {0, 3, 12});
  return s;
}

const std::vector<std::pair<std::string, std::function<Scene()>>>& registry() {
  static const std::vector<std::pair<std::string, std::function<Scene()>>> r = {
      {"lee-flat", [] { return lee(false); }},
      {"lee-terrain", [] { return lee(true); }},
      {"crum-torus", crum_torus},
      {"crum-smooth", crum_smooth},
      {"crum-lattice", crum_lattice},
      {"crum-mandelbulb", crum_mandelbulb},
      {"fogerty", fogerty},
      {"warped", warped},
      {"flafla-torus", flafla_torus},
      {"flafla-csg", flafla_csg},
      {"flafla-materials", flafla_materials},
      {"flafla-animated", flafla_animated},
  };
  return r;
}

}  // namespace

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const auto& [name, make_scene] : registry()) names.push_back(name);
  return names;
}

Scene builtin_scene(const std::string& name) {
  for (const auto& [n, make_scene] : registry())
    if (n == name) return make_scene();
  std::string names;
  for (const auto& [n, make_scene] : registry()) names += (names.empty() ? "" : ", ") + n;
  throw SceneError(name + ": not a built-in scene (" + names + ") and not a scene file path ending in .json");
}

Scene resolve_scene(const std::string& name_or_path) {
  if (name_or_path.size() > 5 && name_or_path.ends_with(".json")) return load_scene_file(name_or_path);
  return builtin_scene(name_or_path);
}

}  // namespace marchcheck::sdf
