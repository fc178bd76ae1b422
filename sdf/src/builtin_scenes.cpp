#include "marchcheck/sdf/builtin_scenes.hpp"

#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/noise.hpp"
#include "marchcheck/sdf/scene_file.hpp"

#include "marchcheck/meshes/procedural.hpp"

#include <cmath>
#include <numbers>
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

// The seed's ground texture: the soil picture at fract(0.2 p.xz), used as it is.
void soil_ground(Material& m) {
  m.texture = TextureMapping::planar;
  m.texture_scale = 0.2;
  m.color = glm::dvec3(1);
}

// A shader's own view: the ray (x, y, 1) turned by a rotation (+x right, +z forward), written to the framebuffer
// as it is.
void shader_view(Scene& s) {
  s.camera.axes = CameraAxes::shader;
  s.output_transfer = OutputTransfer::linear;
}

// lee, the final listing: sphere r 1 at the origin over the ground y + 1.2 (+ the terrain's height); the camera
// orbits the origin at distance 6, pitch 0.3 rad, eye on -z at yaw 0 (a shader's axes), f = 600 px, the lens's
// k1 = 0.3 applied forward (the ray through the distorted point); a point light circling at (6 sin 0.3t, 5,
// 6 cos 0.3t); hard shadows darkening diffuse to 0.3; Phong specular added in shadow too.
// The terrain's lattice hash: splitmix64 (the fix: the same function in every precision) unless the seed's is asked.
Scene lee(bool terrain, NoiseHash hash = NoiseHash::splitmix) {
  Scene s = base(terrain ? "lee-terrain" : "lee-flat",
                 terrain ? "Sphere over a value-noise height-field terrain (SDF y + height(x,z)), marched at f/L; its "
                           "lattice hash is splitmix64, the same function in every precision (the fix for the seed's "
                           "sin hash)"
                         : "Sphere over a ground plane, orbit camera with lens distortion, hard shadows, specular");
  const int ball = add_material(s, "sphere", {0.5, 0.7, 1.0});
  const int ground = add_material(s, "ground", {0.57, 0.42, 0.3});
  s.materials[0].specular = SpecularModel::phong;
  s.materials[0].specular_strength = 0.3;
  s.materials[0].density = 0.2;
  s.materials[1].specular = SpecularModel::phong;
  s.materials[1].specular_strength = 0.05;
  s.materials[1].density = 10;
  for (auto& m : s.materials) m.shininess = 10;
  Node floor = terrain ? make(Op::heightfield,
                              {{"hash", {static_cast<double>(hash)}}, {"octaves", {-0.5, 0.5, -0.05, 2, -0.012, 4}}},
                              {}, ground)
                       : plane({0, 1, 0}, 0, ground);
  s.root = unite({sphere(1, ball), translate({0, -1.2, 0}, std::move(floor))});
  s.camera.model = CameraModel::intrinsics;
  s.camera.pose = CameraPose::orbit;
  s.camera.target = glm::dvec3(0);
  s.camera.distance = 6;
  s.camera.yaw_deg = 0;
  s.camera.pitch_deg = 0.3 * 180 / std::numbers::pi;
  s.camera.fx = s.camera.fy = 600;
  s.camera.k1 = 0.3;
  s.camera.lens = LensConvention::shader;
  shader_view(s);
  Light light = point_light({0, 5, 0}, {1, 1, 1});
  light.motion_sin = {6, 0, 0};
  light.motion_cos = {0, 0, 6};
  light.motion_rate = glm::dvec3(0.3);
  light.shadow = ShadowMode::hard;
  light.bias = ShadowBias::scaled;  // the fix: the seed's 10 * SURF_DIST fails at other scales
  light.darkening = 0.3;
  light.specular_in_shadow = true;
  s.lights = {light};
  s.march.max_steps = 200;
  s.march.max_dist = 100;
  s.march.hit_eps = 0.01;
  s.march.normal_eps = 0.01;
  s.effects.ambient = 0;
  s.effects.background = {0, 0, 0};
  // Rays grazing the ground toward the horizon need more than the seed's 200 steps: up to 1% stay undecided.
  s.limits["hit.undecided"] = 0.01;
  if (terrain) {
    // Central differences at the seed's eps 0.01 across noise features of 0.25 units.
    s.limits["normal.angle_p99_deg"] = 5;
    s.march.marcher = Marcher::scaled;  // the height field's Lipschitz bound is above 1
    soil_ground(s.materials[1]);
  }
  return s;
}

// The sphere's texture at the seed's (polar angle / pi, longitude / 2 pi) about its centre, the ground's the soil.
Scene lee_textured() {
  Scene s = lee(false);
  s.name = "lee-textured";
  s.description = "lee-flat with the soil texture at fract(0.2 p.xz) on the ground and a latitude/longitude one on "
                  "the sphere";
  s.materials[0].texture = TextureMapping::spherical;
  s.materials[0].color = glm::dvec3(1);
  s.materials[0].texture_origin = glm::dvec3(0);  // the sphere's centre
  soil_ground(s.materials[1]);
  return s;
}

Scene lee_glass() {
  Scene s = lee(false);
  s.name = "lee-glass";
  s.description = "lee-flat with the transparent sphere its density announces: refraction (ior 1.5) with Schlick "
                  "Fresnel";
  s.materials[0].transparency = 0.9;
  s.materials[0].ior = 1.5;
  s.effects.max_bounces = 3;
  return s;
}

// The seed's shadow bias, 10 * SURF_DIST along the normal, with SURF_DIST raised to 0.05: shadow rays start
// 0.5 above the ground, beyond the sphere's 0.2 clearance, and the shadow under it leaks. (The scaled strategy
// starts 2 * SURF_DIST = 0.1 up and holds.) Time 5.236 swings the light to the side so the shadow is in view.
Scene lee_flat_defect_bias() {
  Scene s = lee(false);
  s.name = "lee-flat-defect-bias";
  s.description = "lee-flat with SURF_DIST 0.05 and the seed's fixed 10 * SURF_DIST shadow offset: shadows leak";
  s.defects = {"bias"};
  s.time = 5.236;
  s.march.hit_eps = 0.05;
  s.lights[0].bias = ShadowBias::seed_offset;
  return s;
}

// The seed's miss: +inf, shaded anyway at ro + inf rd, so every background pixel's colour is NaN.
Scene lee_flat_defect_nan() {
  Scene s = lee(false);
  s.name = "lee-flat-defect-nan";
  s.description = "lee-flat shading its misses as the seed does: a miss returns +inf and is shaded at ro + inf rd, so "
                  "the pixel's colour is NaN (black on llvmpipe, anything on another driver)";
  s.defects = {"nan"};
  s.march.reading = RecordReading::seed_infinity;
  return s;
}

Scene lee_terrain_defect_lipschitz() {
  Scene s = lee(true);
  s.name = "lee-terrain-defect-lipschitz";
  s.description = "lee-terrain marched by plain sphere tracing although the height field's Lipschitz bound is 1.31";
  s.defects = {"lipschitz"};
  s.march.marcher = Marcher::sphere;
  return s;
}

// The seed's corner hash, fract(sin(dot(c, (12.9898, 54.233))) * 43758.5453123), in the march's float as its shader
// computes it: in float the terrain is another one than in double (the references'), the more so the farther a
// cell lies from the origin.
Scene lee_terrain_defect_hash() {
  Scene s = lee(true, NoiseHash::seed_sin);
  s.name = "lee-terrain-defect-hash";
  s.description = "lee-terrain with the seed's sin hash computed in float: the terrain moves with precision and with "
                  "the distance from the origin";
  s.defects = {"hash"};
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
  s.effects.ao = AmbientOcclusion::steps;
  s.effects.ao_steps_scale = 1.0 / 3000;
  s.output_transfer = OutputTransfer::linear;  // written to the framebuffer as it is
}

Scene crum_torus() {
  Scene s = base("crum-torus", "Torus (1.0, 0.3) in the xz plane under four coloured point lights");
  const int m = add_material(s, "torus", {1, 1, 1});
  s.root = torus(1.0, 0.3, m);
  crum_common(s);
  return s;
}

Scene crum_torus_defect_fov() {
  Scene s = crum_torus();
  s.name = "crum-torus-defect-fov";
  s.description = "crum-torus with the seed's ray direction z = height / tan(fov/2): the real field of view is "
                  "narrower than the stated 70 degrees";
  s.defects = {"fov"};
  s.camera.fov_full_height = true;
  return s;
}

// The seed's CSG demo shapes: a sphere and a box at the origin, combined by its broken operators.
Scene crum_csg_defect(bool intersect_defect) {
  Scene s = base(intersect_defect ? "crum-smooth-defect-intersect" : "crum-smooth-defect-subtract",
                 intersect_defect ? "The seed's intersection max(d2, d2): ignores the sphere, draws only the box"
                                  : "The seed's subtraction max(d2, -d2): draws the box's surface as a zero-thickness shell");
  const int m = add_material(s, "csg", {1, 1, 1});
  Node a = sphere(0.45), b = box(glm::dvec3(0.35));
  if (intersect_defect) {
    s.root = intersect(b, b);
    s.intended = intersect(a, b);
  } else {
    s.root = subtract(b, b);
    s.intended = subtract(b, a);
  }
  s.root.material = m;
  s.intended->material = m;
  s.defects = {intersect_defect ? "intersect" : "subtract"};
  crum_common(s);
  look_at(s, {-0.9, 1.1, 1.4}, {0, 0, 0}, 70);
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
  // Steps of f/2.5 through the open cells leave 11% of rays undecided at the seed's 255 steps.
  s.march.max_steps = 1024;
  // Hits reach t = 480, where float coordinates round by 3e-5: differences over a fixed 1e-4 lose the normal
  // (p99 2.5 degrees, up to 8 at the far hits). An epsilon growing with t keeps it above the rounding.
  s.march.normal_eps_scaled = true;
  s.march.normal_eps = 1e-5;
  return s;
}

Scene crum_lattice_defect_lipschitz() {
  Scene s = crum_lattice();
  s.name = "crum-lattice-defect-lipschitz";
  s.description = "crum-lattice marched by plain sphere tracing although the displacement raises L to 2.5";
  s.defects = {"lipschitz"};
  s.march.marcher = Marcher::sphere;
  return s;
}

Scene crum_mandelbulb() {
  Scene s = base("crum-mandelbulb", "Power-8 Mandelbulb distance estimator, 8 iterations, bailout 2");
  const int m = add_material(s, "bulb", {1, 1, 1});
  s.root = make(Op::mandelbulb, {{"power", {8}}, {"iterations", {8}}, {"bailout", {2}}}, {}, m);
  crum_common(s);
  look_at(s, {-1.1, 1.5, 2.0}, {0, 0, 0}, 70);
  s.march.marcher = Marcher::scaled;
  // Measured against the set the estimate stands for (validation's escape-time reference): near it the
  // estimate falls to 1/40 of the distance, so at crum's threshold of 1e-4 a hit can stop two pixel footprints
  // off the set; 3e-5 keeps every hit within one. Rays grazing the set then need up to ~600 steps (at 255,
  // 0.6% end undecided).
  s.march.hit_eps = 3e-5;
  s.march.max_steps = 600;
  // The glow the article shows (its listing draws none on the torus): misses glow from the smallest |f| seen.
  s.effects.glow = 0.6;
  s.effects.glow_width = 0.3;
  return s;
}

Scene fogerty() {
  Scene s = base("fogerty", "Toon-shaded sphere of radius 3 seen from (0, 0, -10) with a 90 degree field of view");
  const int m = add_material(s, "toon", {1, 0, 0});
  s.materials[0].specular = SpecularModel::phong;  // reflect(-l, n) . to_camera, despite the seed's comment
  s.materials[0].specular_strength = 1;
  s.materials[0].shininess = 4;
  s.root = sphere(3, m);
  look_at(s, {0, 0, -10}, {0, 0, 0}, 90);
  shader_view(s);  // ray normalize(u aspect, v, 1)
  // (mix(-1.5, 1.5, sin(t)/2 + 1/2), 3 + mix(-1.5, 1.5, sin(1.3 t)/2 + 1/2), -10) = (0, 3, -10) + 1.5 (sin t,
  // sin 1.3t, 0).
  Light light = point_light({0, 3, -10}, {1, 1, 1});
  light.motion_sin = {1.5, 1.5, 0};
  light.motion_rate = {1, 1.3, 0};
  s.lights = {light};
  // The fix for the 32-step silhouette: hits within a pixel's footprint, and room to converge.
  s.march.max_steps = 256;
  s.march.hit_eps = 1e-4;
  s.march.eps_mode = EpsMode::pixel;
  s.march.max_dist = 10000;
  s.march.normal_eps = 1e-3;
  s.effects.background = glm::dvec3(0.7);
  s.effects.ambient = 0;
  s.effects.shading = Shading::toon;
  s.effects.toon_bands = 4;
  s.effects.silhouette = 0.2;
  return s;
}

Scene fogerty_defect(const std::string& which) {
  Scene s = fogerty();
  s.name = "fogerty-defect-" + which;
  s.defects = {which};
  s.march.max_steps = 32;
  s.march.eps_mode = EpsMode::absolute;
  if (which == "steps") {
    s.description = "fogerty with the seed's 32 steps and absolute eps 1e-4: silhouette rays end undecided, and the "
                    "seed shades them as hits where they stopped (a black rim)";
    s.march.reading = RecordReading::seed_distance;
  } else if (which == "miss0") {
    s.description = "fogerty read as the seed reads its march: a distance alone, 0 for a miss, which a hit at the ray "
                    "origin also returns";
    s.march.max_steps = 256;
    s.march.reading = RecordReading::seed_distance;
  } else if (which == "mediump") {
    // binary16 spaces values 2^-9 apart at |p| in [2, 4): twenty times the hit threshold, and the normal's 1e-3
    // offsets round to 0 or to one spacing, so central differences give no direction or a wrong one.
    s.description = "fogerty in the seed's mediump (IEEE binary16, as GPUs that honour it run it) with its absolute "
                    "hit threshold 1e-4: hits and normals are noise at the scale binary16 resolves, the surface is "
                    "speckled";
    s.march.max_steps = 256;
    s.march.precision = Precision::float16;
  } else {
    s.description = "fogerty with the ray direction passed where the camera position belongs: wrong specular and "
                    "silhouette";
    s.march.max_steps = 256;
    s.march.eps_mode = EpsMode::pixel;
    s.effects.eye_is_ray_direction = true;
  }
  return s;
}

Scene warped() {
  Scene s = base("warped", "Sphere of radius 2 whose centre is displaced by time-varying sinusoids (time = 1)");
  const int m = add_material(s, "warped", {1, 1, 1});
  s.root = make(Op::warp, {}, {sphere(2, m)});
  s.time = 1;
  look_at(s, {0, 0, -1}, {0, 0, 1}, 90);
  shader_view(s);  // rays along (x, y, 1)
  s.lights = {directional_light({-1, -1, 1}, {1, 0.1, 0.1}), directional_light({1, -1, 1}, {0, 0.25, 0}),
              directional_light({0, 1, 1}, {0, 0, 0.25})};
  s.march.max_steps = 256;
  // The seed's 0.02 leaves hits visibly off a surface this steep (normals off by 37 degrees at the 99th
  // percentile); 0.002 brings that under 4.
  s.march.hit_eps = 0.002;
  s.limits["normal.angle_p99_deg"] = 5;
  s.march.max_dist = 100;
  s.march.normal = NormalMethod::forward;
  s.march.marcher = Marcher::scaled;  // the warp's slope reaches 4: step by f / L
  s.effects.ambient = 0;
  return s;
}

Scene warped_defect(const std::string& which) {
  Scene s = warped();
  s.name = "warped-defect-" + which;
  s.defects = {which};
  if (which == "unnormalised") {
    s.description = "warped with the seed's ray direction (x, y, 1) not normalised: every step is up to 1.7x too long";
    s.camera.normalize_rays = false;
  } else {
    s.description = "warped marched by plain sphere tracing although the warp's Lipschitz bound is 4.5";
    s.march.marcher = Marcher::sphere;
  }
  return s;
}

// Unity's view space is left-handed; seen from +z in this right-handed one, +x is on the right as there.
void flafla_common(Scene& s, glm::dvec3 eye) {
  look_at(s, eye, {0, 0, 0}, 60);
  s.march.max_steps = 64;
  s.march.hit_eps = 0.001;
  s.march.max_dist = 40;
  s.march.normal_eps = 0.001;
  s.lights = {directional_light({-0.3, -1, -0.5}, {1, 1, 1})};
  s.effects.diffuse = Diffuse::unclamped;  // Unity's dot(-light_dir, n), not clamped
  s.effects.ambient = 0;
}

Scene flafla_torus() {
  Scene s = base("flafla-torus", "Unity image-effect marcher: torus (1, 0.2), 64 steps, draw distance 40");
  const int m = add_material(s, "torus", {0.9, 0.9, 0.9});
  s.root = torus(1, 0.2, m);
  flafla_common(s, {0, 2, 4});
  return s;
}

SceneMesh box_mesh(std::string name, glm::dvec3 c, glm::dvec3 h, int material) {
  SceneMesh m{meshes::box(h).mesh, std::move(name), material};
  for (auto& v : m.vertices) v += c;
  return m;
}

// The Unity seed's mesh occlusion: a triangle-mesh box through the marched torus; each hides the other.
Scene flafla_occlusion() {
  Scene s = flafla_torus();
  s.name = "flafla-occlusion";
  s.description = "flafla-torus sharing the screen with a triangle-mesh box: the march stops at the mesh's distance";
  const int mesh_material = add_material(s, "mesh", {0.9, 0.5, 0.2});
  s.meshes = {box_mesh("box", {1, 0, 0}, {0.3, 0.6, 0.3}, mesh_material)};
  return s;
}

Scene flafla_torus_defect_no_drawdist() {
  Scene s = flafla_torus();
  s.name = "flafla-torus-defect-no-drawdist";
  s.description = "flafla-torus without a draw distance: every miss spends all 64 steps and ends undecided";
  s.defects = {"no-drawdist"};
  s.march.max_dist = INFINITY;
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
  const int torus_m = add_material(s, "ramp-0.5", {1, 1, 1});
  const int box_m = add_material(s, "ramp-0.25", {1, 1, 1});
  const int sphere_m = add_material(s, "ramp-0.75", {1, 1, 1});
  s.materials[0].ramp_value = 0.5;
  s.materials[1].ramp_value = 0.25;
  s.materials[2].ramp_value = 0.75;
  s.effects.ramp = {{0.1, 0.2, 0.9}, {0.1, 0.8, 0.3}, {0.95, 0.25, 0.1}};  // blue, green, red
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

// A shape over a ground plane, seen from above one side, under a directional light with hard shadows.
void mesh_stage(Scene& s, Node shape, glm::dvec3 eye) {
  const int ground = add_material(s, "ground", {0.6, 0.6, 0.55});
  s.root = unite({std::move(shape), plane({0, 1, 0}, 0, ground)});
  look_at(s, eye, {0, 0.8, 0}, 45);
  Light sun = directional_light({-0.4, -1, -0.3}, {1, 1, 1});
  sun.shadow = ShadowMode::hard;
  s.lights = {sun};
  s.march.max_dist = 60;
}

// A mesh of the analytic sphere beside that sphere: their hits differ by at most the mesh's chord error.
Scene mesh_icosphere() {
  Scene s = base("mesh-icosphere", "Icosphere mesh of radius 1 (5120 triangles, exact mesh distance) beside the "
                                   "analytic unit sphere, over a ground plane, hard shadows");
  const int m = add_material(s, "mesh", {0.85, 0.55, 0.3});
  const int a = add_material(s, "sphere", {0.4, 0.6, 0.9});
  mesh_stage(s,
             unite({translate({-1.25, 1.1, 0}, mesh("procedural:icosphere(1,4)", m)),
                    translate({1.25, 1.1, 0}, sphere(1, a))}),
             {0, 2.6, 6.5});
  // Central differences within normal_eps of a mesh edge see both of its faces: there the normal error reaches
  // the angle between adjacent faces' normals, at most 2.88 degrees on icosphere(1,4) (a test measures it).
  // Edges are too many to leave out of the 99th percentile (about 1 hit in 10 is that near one).
  s.limits["normal.angle_p99_deg"] = 2.9;
  return s;
}

// Sharp convex and concave edges, and vertices where coplanar triangles fan out at many angles: where a face's
// own normal gives the wrong sign and the pseudonormals do not.
Scene mesh_box() {
  Scene s = base("mesh-box", "Box mesh with one octant cut away (48 triangles, exact mesh distance), turned "
                             "25 degrees about y over a ground plane, hard shadows");
  const int m = add_material(s, "mesh", {0.7, 0.75, 0.8});
  Node shape = make(Op::rotate, {{"axis", {0, 1, 0}}, {"angle_deg", {25}}},
                    {mesh("procedural:notched_box(1,0.7,0.6)", m)});
  mesh_stage(s, translate({0, 0.9, 0}, std::move(shape)), {3, 3.2, 5});
  return s;
}

const std::vector<std::pair<std::string, std::function<Scene()>>>& registry() {
  static const std::vector<std::pair<std::string, std::function<Scene()>>> r = {
      {"lee-flat", [] { return lee(false); }},
      {"lee-terrain", [] { return lee(true); }},
      {"lee-textured", lee_textured},
      {"lee-glass", lee_glass},
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
      {"flafla-occlusion", flafla_occlusion},
      {"mesh-icosphere", mesh_icosphere},
      {"mesh-box", mesh_box},
      // Defect variants: each reproduces one seed defect faithfully; `scenes` lists them as such.
      {"lee-flat-defect-bias", lee_flat_defect_bias},
      {"lee-flat-defect-nan", lee_flat_defect_nan},
      {"lee-terrain-defect-lipschitz", lee_terrain_defect_lipschitz},
      {"lee-terrain-defect-hash", lee_terrain_defect_hash},
      {"crum-torus-defect-fov", crum_torus_defect_fov},
      {"crum-smooth-defect-intersect", [] { return crum_csg_defect(true); }},
      {"crum-smooth-defect-subtract", [] { return crum_csg_defect(false); }},
      {"crum-lattice-defect-lipschitz", crum_lattice_defect_lipschitz},
      {"fogerty-defect-steps", [] { return fogerty_defect("steps"); }},
      {"fogerty-defect-miss0", [] { return fogerty_defect("miss0"); }},
      {"fogerty-defect-camera", [] { return fogerty_defect("camera"); }},
      {"fogerty-defect-mediump", [] { return fogerty_defect("mediump"); }},
      {"warped-defect-unnormalised", [] { return warped_defect("unnormalised"); }},
      {"warped-defect-lipschitz", [] { return warped_defect("lipschitz"); }},
      {"flafla-torus-defect-no-drawdist", flafla_torus_defect_no_drawdist},
  };
  return r;
}

}  // namespace

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const auto& [name, make_scene] : registry()) names.push_back(name);
  return names;
}

Scene builtin_scene(const std::string& name, const MeshLoader& loader) {
  for (const auto& [n, make_scene] : registry())
    if (n == name) {
      Scene s = make_scene();
      try {
        load_meshes(s, loader);
      } catch (const SceneError& e) {
        throw SceneError(name + ": " + e.what());
      }
      return s;
    }
  std::string names;
  for (const auto& [n, make_scene] : registry()) names += (names.empty() ? "" : ", ") + n;
  throw SceneError(name + ": not a built-in scene (" + names + ") and not a scene file path ending in .json");
}

Scene resolve_scene(const std::string& name_or_path, const MeshLoader& loader) {
  if (name_or_path.size() > 5 && name_or_path.ends_with(".json")) return load_scene_file(name_or_path, loader);
  if (name_or_path.size() > 5 && name_or_path.ends_with(".glsl")) return glsl_scene(name_or_path);
  return builtin_scene(name_or_path, loader);
}

}  // namespace marchcheck::sdf
