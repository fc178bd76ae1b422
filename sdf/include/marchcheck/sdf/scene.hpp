// A scene: the field, its materials, lights, camera, declared effects, marching parameters and check limits.
// Plain data: the marchers and renderer (march/) read it, scene files (JSON) write and read it.
#pragma once

#include "marchcheck/sdf/node.hpp"

#include <glm/glm.hpp>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace marchcheck::sdf {

enum class Marcher { sphere, relaxed, fixed, scaled };
enum class EpsMode { absolute, relative, pixel };
enum class NormalMethod { central, forward, tetra, analytic };
enum class ShadowMode { none, hard, soft };
enum class Precision { single, dual };  // float or double arithmetic in the march

struct MarchSettings {
  Marcher marcher = Marcher::sphere;
  int max_steps = 200;
  double max_dist = 100;
  double hit_eps = 0.01;
  EpsMode eps_mode = EpsMode::absolute;
  double step_scale = 1;    // multiplies every step (sphere, relaxed, scaled)
  double relaxation = 1.6;  // over-relaxation factor of the relaxed marcher
  double fixed_step = 0.05;
  NormalMethod normal = NormalMethod::central;
  double normal_eps = 1e-3;
  bool normal_eps_scaled = false;  // normal_eps * t instead of an absolute epsilon
  ShadowMode shadow = ShadowMode::hard;
  double shadow_bias = 0.1;
  Precision precision = Precision::single;
};

struct Material {
  std::string name;
  glm::dvec3 color{0.8};
};

enum class LightType { point, directional };

struct Light {
  LightType type = LightType::directional;
  glm::dvec3 position{0, 5, 0};
  glm::dvec3 direction{0, -1, 0};  // direction the light travels, for directional lights
  glm::dvec3 color{1};
};

enum class CameraModel { pinhole, intrinsics, frustum, orthographic };
enum class CameraPose { look_at, orbit };

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
};

struct Effects {
  glm::dvec3 background{0};
  double ambient = 0.1;
};

struct Scene {
  std::string name;
  std::string description;
  Node root;
  double time = 0;
  int width = 640, height = 360;
  CameraSpec camera;
  std::vector<Material> materials;
  std::vector<Light> lights;
  Effects effects;
  MarchSettings march;
  std::map<std::string, double> limits;  // per-check limits this scene sets
};

struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Index of the named material; -1 when there is none.
int find_material(const Scene& scene, std::string_view name);

// Applies one KEY=VALUE override (march parameters, time, width, height, camera.*). Throws SceneError naming
// the key and what was expected.
void apply_setting(Scene& scene, std::string_view key, std::string_view value);
// The keys apply_setting accepts.
std::vector<std::string> setting_keys();

}  // namespace marchcheck::sdf
