#include "lee_flat_port.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <glm/glm.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace marchcheck::bench {

namespace {

using glm::vec3;

constexpr int kMaxSteps = 200;
constexpr float kMaxDist = 100, kSurfDist = 0.01f;

// The shader's GetDist: sphere at the origin, radius 1, united with the ground y + 1.2.
float get_dist(vec3 p) {
  const float sphere = glm::length(p) - 1.0f;
  return glm::min(sphere, p.y + 1.2f);
}

// Material 1 (ground) where the ground is nearer, else 0 (sphere); one more call of the field, as the renderer's.
int get_material(vec3 p) { return p.y + 1.2f < glm::length(p) - 1.0f ? 1 : 0; }

struct March {
  float t = 0;
  bool hit = false;
};

// The shader's RayMarch: counts its calls of get_dist into evals. A first step below -SURF_DIST starts inside.
March ray_march(vec3 ro, vec3 rd, float max_dist, std::uint64_t& evals) {
  March m;
  for (int i = 0; i < kMaxSteps; ++i) {
    const float d = get_dist(ro + rd * m.t);
    ++evals;
    if (i == 0 && d < -kSurfDist) return {m.t, true};
    if (d < kSurfDist) return {m.t, true};
    m.t += d;
    if (m.t > max_dist) return m;
  }
  return m;
}

vec3 get_normal(vec3 p, std::uint64_t& evals) {
  const float e = 0.01f;
  evals += 6;
  const vec3 g(get_dist(p + vec3(e, 0, 0)) - get_dist(p - vec3(e, 0, 0)),
               get_dist(p + vec3(0, e, 0)) - get_dist(p - vec3(0, e, 0)),
               get_dist(p + vec3(0, 0, e)) - get_dist(p - vec3(0, 0, e)));
  return g / glm::length(g);
}

vec3 shade(vec3 ro, vec3 rd, vec3 light_pos, std::uint64_t& evals) {
  const March m = ray_march(ro, rd, kMaxDist, evals);
  if (!m.hit) return vec3(0);
  const vec3 p = ro + rd * m.t;
  const vec3 n = get_normal(p, evals);
  const int material = get_material(p);
  ++evals;
  // Hard shadow from just above the surface: twice SURF_DIST plus the rounding of |p| and t.
  const vec3 to_light = light_pos - p;
  const float light_dist = glm::length(to_light);
  const float magnitude = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) + m.t;
  const float lift = 2 * kSurfDist + 10 * std::numeric_limits<float>::epsilon() * magnitude;
  const March shadow = ray_march(p + n * lift, to_light / light_dist, std::min(kMaxDist, light_dist), evals);
  const float visible = shadow.hit ? 0.0f : 1.0f;

  const vec3 albedo = material == 0 ? vec3(0.5f, 0.7f, 1.0f) : vec3(0.57f, 0.42f, 0.3f);
  const float strength = material == 0 ? 0.3f : 0.05f;
  const vec3 l = glm::normalize(to_light);
  const float diffuse = glm::clamp(glm::dot(n, l), 0.0f, 1.0f);
  const float specular = strength * std::pow(glm::clamp(glm::dot(glm::reflect(-l, n), glm::normalize(ro - p)), 0.0f, 1.0f), 10.0f);
  // The specular is added in shadow too, as the seed adds it.
  return glm::max(albedo * diffuse * glm::mix(0.3f, 1.0f, visible) + vec3(specular), vec3(0));
}

}  // namespace

PortImage render_lee_flat_port(const sdf::Scene& lee_flat) {
  PortImage image;
  image.width = lee_flat.width;
  image.height = lee_flat.height;
  image.rgb.resize(static_cast<size_t>(image.width) * image.height * 3);
  const march::Camera camera(lee_flat.camera, image.width, image.height);
  const vec3 light_pos(lee_flat.lights.at(0).position_at(lee_flat.time));
  std::atomic<std::uint64_t> evals{0};  // one add per row
  tbb::parallel_for(0, image.height, [&](int y) {
    std::uint64_t row_evals = 0;
    for (int x = 0; x < image.width; ++x) {
      const march::Ray ray = camera.ray(x + 0.5, y + 0.5);
      const vec3 c = shade(vec3(ray.origin), vec3(ray.direction), light_pos, row_evals);
      float* out = &image.rgb[(static_cast<size_t>(y) * image.width + x) * 3];
      for (int i = 0; i < 3; ++i) out[i] = c[i];
    }
    evals += row_evals;
  });
  image.evals = evals;
  return image;
}

}  // namespace marchcheck::bench
