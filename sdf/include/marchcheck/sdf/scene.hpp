// A scene: the field, its materials, lights, camera, declared effects, marching parameters and check limits.
// Plain data: the marchers and renderer (march/) read it, scene files (JSON) write and read it.
#pragma once

#include "marchcheck/meshes/mesh.hpp"
#include "marchcheck/sdf/node.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace marchcheck::sdf {

enum class Marcher { sphere, relaxed, fixed, scaled };
enum class EpsMode { absolute, relative, pixel };
// What a sphere-traced hit's t becomes (sphere, relaxed and scaled; the fixed marcher's bisection is its own):
// none: where the march stopped; secant: one Newton step on f(o + t d) = 0 with the derivative along the ray
// taken from the last two samples (march::secant_root), kept where one more evaluation finds |f| smaller there:
// an error of O(eps^2) for O(eps) on a smooth surface.
enum class HitRefine { none, secant };
// Which part of a ray is marched. none: all of it, to max_dist; bounds: only from where it first enters to where it
// last leaves the boxes the field's zero set and inside lie in (bounding_boxes), so a ray that misses them ends after
// no evaluation and one that leaves them ends there (march::clip_span).
enum class Clip { none, bounds };
// What bounds a step of the marchers that honour L (scaled, relaxed). lipschitz: f / L. perturbed: on a field that
// is a smooth one plus a perturbation within a band (FieldInfo::perturbation: a height field's noise, a
// displacement), also (f - width) / the smooth part's L where that is longer: far from a displaced surface, steps
// near f instead of f / L. Shadow rays keep f / L.
enum class StepBound { lipschitz, perturbed };
enum class NormalMethod { central, forward, tetra, analytic };
enum class ShadowMode { none, hard, soft };
// Where a hard shadow ray starts and which hits count. seed_offset: start at p + bias * hit_eps * n (Lee's
// 10 * SURF_DIST); seed_ignore: start at p + hit_eps * n and ignore hits closer than bias * hit_eps; scaled:
// start at p + n * (hit threshold at t + bias * float epsilon * (|p| + t)), which holds at any scene scale.
enum class ShadowBias { seed_offset, seed_ignore, scaled };
enum class SoftShadow { classic, improved };
// The march's arithmetic: float, double, or float16: GLSL's mediump as mobile GPUs run it, the march in float
// with every field evaluation in IEEE binary16 (the tape's and each GLSL field's).
enum class Precision { float32, float64, float16 };
// How the scene's consumer reads a march. outcome: the record's own outcome. seed_distance: the fogerty seed's,
// which gets a distance alone (0 past max_dist, wherever the march stopped otherwise) and shades any t > 0: a ray
// that ran out of steps is drawn as a hit where it stopped, and a miss cannot be told from a hit at the ray origin.
// seed_infinity: the lee seed's, whose miss returns +inf and is shaded anyway at ro + inf rd: the pixel's colour
// is NaN (black on llvmpipe, anything on another driver).
enum class RecordReading { outcome, seed_distance, seed_infinity };
// What the march's positions are measured from. world: the origin, as a shader computes them (float's spacing
// grows with the distance from it). camera: the eye, the scene rewritten about it in double before anything is
// rounded (march::camera_relative), so a scene far from the origin keeps float's precision near the camera.
enum class Coordinates { world, camera };

// The over-relaxation factors a relaxed march takes: [1, 2). At 2 the relaxed step's fallback test (two
// unbounding spheres that must overlap) no longer holds. Scene files and --set refuse others; a march given one
// anyway (from code) returns `invalid`.
inline constexpr double kRelaxationMin = 1, kRelaxationMax = 2;  // the maximum excluded
inline bool relaxation_valid(double omega) { return omega >= kRelaxationMin && omega < kRelaxationMax; }

struct MarchSettings {
  Marcher marcher = Marcher::sphere;
  int max_steps = 200;
  double max_dist = 100;
  double hit_eps = 0.01;
  EpsMode eps_mode = EpsMode::absolute;
  HitRefine refine = HitRefine::none;
  Clip clip = Clip::none;
  StepBound step_bound = StepBound::lipschitz;
  double step_scale = 1;    // multiplies every step (sphere, relaxed, scaled)
  double relaxation = 1.6;  // over-relaxation factor of the relaxed marcher
  double fixed_step = 0.05;
  NormalMethod normal = NormalMethod::central;
  double normal_eps = 1e-3;
  bool normal_eps_scaled = false;  // normal_eps * t instead of an absolute epsilon
  Precision precision = Precision::float32;
  RecordReading reading = RecordReading::outcome;
  Coordinates coordinates = Coordinates::world;
};

// How far a step goes per unit of f on a field of declared Lipschitz bound L: step_scale, over L for the marchers
// that honour L (scaled; relaxed, whose over-relaxed step and unbounding spheres build on f / L). The sphere marcher
// steps by f whatever L is, as the seeds do; the fixed marcher does not step by f. Marches, soft shadows, the
// validator's safe-step check and the exported GLSL marcher all step by this one rule.
inline bool honours_lipschitz(Marcher m) { return m == Marcher::scaled || m == Marcher::relaxed; }
inline double step_per_unit_f(const MarchSettings& m, double lipschitz) {
  return honours_lipschitz(m.marcher) ? m.step_scale / lipschitz : m.step_scale;
}

// The band a march steps past by the perturbed bound (StepBound::perturbed, a marcher that honours L): the field's
// declared width; else +inf, where (f - width) * anything never beats f * step_per_unit_f.
inline double stepped_perturbation(const MarchSettings& m, double width) {
  return honours_lipschitz(m.marcher) && m.step_bound == StepBound::perturbed ? width : INFINITY;
}

enum class SpecularModel { none, phong, blinn };
enum class TextureMapping { none, planar, spherical };

struct Material {
  std::string name;
  glm::dvec3 color{0.8};
  SpecularModel specular = SpecularModel::none;
  double specular_strength = 0;
  double shininess = 10;
  double reflectivity = 0;  // mirror reflection weight
  double transparency = 0;  // refraction weight (Schlick Fresnel splits it with reflection)
  double ior = 1.5;
  double density = 0;  // the Lee seed's per-material density; kept for scene files, not rendered
  TextureMapping texture = TextureMapping::none;
  double texture_scale = 1;
  glm::dvec3 texture_origin{0};  // what a spherical texture's angles are measured about (a sphere's centre)
  // An image for the texture (any format OpenImageIO reads; a scene file names it relative to itself); "" is the
  // procedural soil. Looked up bilinearly, wrapping periodically, without MIP maps.
  std::string texture_file{};
  double ramp_value = -1;  // >= 0: colour from the scene's ramp at this value
};

enum class LightType { point, directional };

struct Light {
  LightType type = LightType::directional;
  glm::dvec3 position{0, 5, 0};
  glm::dvec3 direction{0, -1, 0};  // direction the light travels, for directional lights
  glm::dvec3 color{1};
  // Point lights move: position + motion_sin sin(motion_rate t) + motion_cos cos(motion_rate t), axis by axis
  // (fogerty's light swings along x at rate 1 and along y at rate 1.3).
  glm::dvec3 motion_sin{0}, motion_cos{0};
  glm::dvec3 motion_rate{0};
  ShadowMode shadow = ShadowMode::none;
  ShadowBias bias = ShadowBias::scaled;
  double bias_factor = 10;
  double darkening = 0;  // light kept in full shadow (Lee: 0.3)
  // The specular highlight stays in shadow (the lee seed adds it whether or not the point is shadowed); off, a
  // shadow takes it away.
  bool specular_in_shadow = false;
  SoftShadow soft = SoftShadow::improved;
  double penumbra = 8;  // soft shadow k

  glm::dvec3 position_at(double time) const {
    return position + motion_sin * glm::sin(motion_rate * time) + motion_cos * glm::cos(motion_rate * time);
  }
};

enum class CameraModel { pinhole, intrinsics, frustum, orthographic };
enum class CameraPose { look_at, orbit };
// Which way the camera's axes run. right_handed: the look-at convention (right = forward x up, so a camera looking
// along +z has world +x on the image's left). shader: the ray (x, y, 1) a shader builds, turned by a rotation: +x
// image right, +y up, +z forward, a left-handed view (looking along +z, world +x is on the right). An orbit at yaw 0
// sits on the side the view looks away from: +z for right_handed, -z for shader.
enum class CameraAxes { right_handed, shader };
// Where lens distortion sits between a pixel and its ray. opencv: the ray's image is the distorted point (a
// calibrated camera: the ray goes through the undistorted pixel coordinates); shader: the ray goes through the
// distorted point, xy <- (1 + k1 r^2 + k2 r^4) xy + tangential terms, with y up (a shader that widens its image).
enum class LensConvention { opencv, shader };

struct CameraSpec {
  CameraModel model = CameraModel::pinhole;
  CameraPose pose = CameraPose::look_at;
  glm::dvec3 position{0, 0, 5};
  glm::dvec3 target{0};
  glm::dvec3 up{0, 1, 0};
  double yaw_deg = 0, pitch_deg = 0, distance = 5;  // orbit pose
  double fov_deg = 60;                              // vertical; pinhole and frustum
  double fx = 600, fy = 600;                        // intrinsics; cx, cy default to the image centre
  double cx = -1, cy = -1;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0;  // Brown-Conrady
  double ortho_height = 4;                // orthographic: world units the image height spans
  // The crum seed's defect: focal length from the full image height instead of half of it.
  bool fov_full_height = false;
  // The warped seed's defect: rays not normalised (direction (x, y, 1) as given).
  bool normalize_rays = true;
  CameraAxes axes = CameraAxes::right_handed;
  LensConvention lens = LensConvention::opencv;
};

// Where a camera stands and which way its axes point (unit vectors; right, up, forward as the image sees them).
struct CameraFrame {
  glm::dvec3 eye, right, up, forward;
};
CameraFrame camera_frame(const CameraSpec& spec);

// The Brown-Conrady coefficients in the image's coordinates (y down), as the camera and the GLSL export apply them:
// a shader's lens (y up) is the same with p1 of the other sign.
struct LensCoefficients {
  double k1, k2, p1, p2;
};
LensCoefficients image_lens(const CameraSpec& spec);

enum class Diffuse { clamped, floor, unclamped };
enum class AmbientOcclusion { none, steps, samples };
enum class Shading { lambert, toon };

struct Effects {
  glm::dvec3 background{0};
  double ambient = 0.1;
  Diffuse diffuse = Diffuse::clamped;
  double diffuse_floor = 0.2;
  Shading shading = Shading::lambert;
  int toon_bands = 4;
  double silhouette = 0;  // toon: black where dot(to camera, n) < silhouette
  AmbientOcclusion ao = AmbientOcclusion::none;
  double ao_steps_scale = 1.0 / 3000;  // steps: colour -= steps^2 * scale
  int ao_samples = 5;
  double ao_distance = 0.1;  // samples: spacing along the normal
  double glow = 0;           // glow on misses from the smallest |f| seen (strength; 0 = off)
  double glow_width = 0.1;
  glm::dvec3 glow_color{1, 0.8, 0.4};
  double fog = 0;  // density per unit distance (0 = off)
  glm::dvec3 fog_color{0.7};
  int max_bounces = 0;  // reflection and refraction depth
  std::vector<glm::dvec3> ramp;  // colour ramp for materials with a ramp value
  // The fogerty seed's defect: the ray direction used where the camera position belongs.
  bool eye_is_ray_direction = false;
};

// A triangle mesh sharing the screen with the marched field (the Unity seed's depth-buffer occlusion): its
// triangles (counter-clockwise seen from outside), its name and its material.
struct SceneMesh : meshes::Mesh {
  std::string name;
  int material = -1;
};

// How colour values become an 8-bit image's. srgb: the sRGB transfer curve (what a display expects of linear
// light); linear: written as they are, as a shader writes them into an 8-bit framebuffer (the seeds do).
enum class OutputTransfer { srgb, linear };

struct Scene {
  std::string name;
  std::string description;
  Node root;
  double time = 0;
  int width = 640, height = 360;
  CameraSpec camera;
  std::vector<Material> materials;
  std::vector<Light> lights;
  std::vector<SceneMesh> meshes;
  Effects effects;
  OutputTransfer output_transfer = OutputTransfer::srgb;
  MarchSettings march;
  std::map<std::string, double> limits;  // per-check limits this scene sets
  // What the scene means to draw when root is a faithful reproduction of a defect (for example the seed's
  // intersection that ignores its first shape): validation builds its references from this tree.
  std::optional<Node> intended;
  std::vector<std::string> defects;  // which seed defects this variant reproduces ("" = a correct scene)
};

struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The effects a scene declares, as short names ("shadow:hard", "specular", "texture", "ao:steps", ...).
std::vector<std::string> declared_effects(const Scene& scene);

// Index of the named material; -1 when there is none.
int find_material(const Scene& scene, std::string_view name);

// The colour a material takes from the scene's ramp (at its ramp value, linearly between the ramp's colours), or
// nothing when it takes none (no ramp value, or no ramp): then its own colour or texture.
std::optional<glm::dvec3> ramp_color(const Scene& scene, const Material& material);

// Applies one KEY=VALUE override (march parameters, time, width, height, camera.*). Throws SceneError
// "KEY[=VALUE]: what was expected"; callers say which option it came from.
void apply_setting(Scene& scene, std::string_view key, std::string_view value);
// The scene's value of a setting as apply_setting takes it back, exactly (numbers in their shortest exact form).
std::string setting_text(const Scene& scene, std::string_view key);
// The same view at another width (height in proportion, intrinsics scaled with it), for cheaper renders.
Scene scaled_to_width(const Scene& scene, int width);
// The same scene moved by offset with everything placed in it (its trees, meshes, camera, point lights and the
// textures' origins), in double: what a far-coordinate study renders.
Scene moved_by(const Scene& scene, glm::dvec3 offset);

}  // namespace marchcheck::sdf
