#include "marchcheck/march/render.hpp"

#include "marchcheck/march/camera_relative.hpp"
#include "marchcheck/march/effects.hpp"
#include "marchcheck/march/mesh_occluder.hpp"
#include "marchcheck/march/normals.hpp"
#include "marchcheck/march/packet.hpp"
#include "marchcheck/march/texture.hpp"
#include "marchcheck/march/tolerances.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numbers>
#include <array>
#include <chrono>
#include <new>
#include <sstream>
#include <stdexcept>

namespace marchcheck::march {

Image::Image(int w, int h, int c, float fill)
    : width(w), height(h), channels(c), pixels(static_cast<size_t>(w) * h * c, fill) {}

Image Image::unset(int w, int h, int c) {
  Image image;
  image.width = w, image.height = h, image.channels = c;
  image.pixels.resize(static_cast<size_t>(w) * h * c);  // PixelAllocator::construct with no value: none set
  return image;
}

std::string_view to_string(Outcome outcome) {
  switch (outcome) {
    case Outcome::hit: return "hit";
    case Outcome::miss_far: return "miss_far";
    case Outcome::miss_steps: return "miss_steps";
    case Outcome::inside: return "inside";
    case Outcome::invalid: return "invalid";
  }
  return "?";
}

bool settings_invalid(const MarchSettings& s, const MarchContext& c) {
  const bool scale_ok = s.step_scale > 0 && std::isfinite(s.step_scale);
  const bool lipschitz_ok = s.marcher != Marcher::scaled || (c.lipschitz > 0 && std::isfinite(c.lipschitz));
  const bool relax_ok = s.marcher != Marcher::relaxed || sdf::relaxation_valid(s.relaxation);
  const bool fixed_ok = s.marcher != Marcher::fixed || (s.fixed_step > 0 && std::isfinite(s.fixed_step));
  const sdf::Perturbation& p = c.perturbation;
  const bool perturbation_ok = sdf::stepped_perturbation(s, p.width) == INFINITY ||
                               (p.lipschitz > 0 && std::isfinite(p.lipschitz) && p.width >= 0);
  const bool eps_ok = s.hit_eps >= 0 && std::isfinite(s.hit_eps) && c.footprint_at_0 >= 0 && c.footprint_slope >= 0;
  return !(s.max_steps >= 0 && s.max_dist > 0 && scale_ok && lipschitz_ok && perturbation_ok && relax_ok && fixed_ok &&
           eps_ok);
}

std::vector<Aov> parse_aovs(const std::string& list) {
  std::vector<Aov> out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item == "depth") out.push_back(Aov::depth);
    else if (item == "normal") out.push_back(Aov::normal);
    else if (item == "steps") out.push_back(Aov::steps);
    else if (item == "evals") out.push_back(Aov::evals);
    else if (item == "id") out.push_back(Aov::id);
    else if (item == "stages") out.push_back(Aov::stages);
    else if (item == "error") out.push_back(Aov::error);
    else throw std::invalid_argument("unknown AOV '" + item + "'; expected depth, normal, steps, evals, id, stages, error");
  }
  return out;
}

std::string to_string(Aov aov) {
  switch (aov) {
    case Aov::depth: return "depth";
    case Aov::normal: return "normal";
    case Aov::steps: return "steps";
    case Aov::evals: return "evals";
    case Aov::id: return "id";
    case Aov::stages: return "stages";
    case Aov::error: return "error";
  }
  return "?";
}

double RenderResult::evals_per_pixel() const {
  const double pixels = static_cast<double>(color.width) * color.height;
  return pixels > 0 ? static_cast<double>(total_evals) / pixels : 0;
}

namespace {

enum Stage { kMesh, kMarch, kNormal, kMaterial, kShadow, kAo, kReflection, kRefraction, kShade, kStageCount };
constexpr const char* kStageNames[kStageCount] = {"mesh", "march",      "normal",     "material", "shadow",
                                                  "ao",   "reflection", "refraction", "shade"};
constexpr int kTile = 16;

struct Counters {
  std::array<StageCost, kStageCount> stages{};
  int steps_max = 0;
};

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// What the scene declares, decided once: a stage not declared is never entered, so it costs nothing.
struct Pipeline {
  bool normals = false, materials = false, shadows = false, ao_samples = false, reflection = false,
       refraction = false, textures = false;
};

Pipeline plan(const sdf::Scene& scene, const std::vector<Aov>& aovs, bool reference) {
  Pipeline p;
  const bool aov_normal = std::find(aovs.begin(), aovs.end(), Aov::normal) != aovs.end();
  const bool aov_id = std::find(aovs.begin(), aovs.end(), Aov::id) != aovs.end();
  const bool lit = !scene.lights.empty();
  p.materials = lit || aov_id || scene.effects.ambient > 0;
  for (const auto& l : scene.lights) p.shadows = p.shadows || l.shadow != sdf::ShadowMode::none;
  p.ao_samples = scene.effects.ao == sdf::AmbientOcclusion::samples;
  for (const auto& m : scene.materials) {
    p.reflection = p.reflection || (m.reflectivity > 0 && scene.effects.max_bounces > 0);
    p.refraction = p.refraction || (m.transparency > 0 && scene.effects.max_bounces > 0);
    p.textures = p.textures || m.texture != sdf::TextureMapping::none;
  }
  p.normals = lit || aov_normal || p.ao_samples || p.reflection || p.refraction ||
              scene.effects.shading == sdf::Shading::toon;
  if (reference) p.ao_samples = p.reflection = p.refraction = false;
  return p;
}

struct Context {
  const sdf::Scene& scene;
  // What the march's positions are measured from (march_origin): rays, points and lights are relative to it;
  // textures and the reference's oracle (world coordinates, double) add it back.
  glm::dvec3 origin;
  sdf::Tape tape;
  Camera camera;
  MarchContext march;
  Pipeline pipeline;
  std::unique_ptr<MeshOccluder> meshes;  // only when the scene has triangle meshes
  const SurfaceOracle* oracle;           // reference renders
  std::vector<glm::dvec3> light_positions;  // at the scene's time, computed once rather than per pixel
  ShadePrecision shade;
  std::vector<std::optional<glm::dvec3>> uniform_colors;  // each material's uniform_color, found once
};

template <class T>
using Vec = glm::vec<3, T>;

// Room for a tile's worth of an aggregate written whole before it is read (a packet call's RayRecord or
// NormalResult, a pixel's mesh hit): left unset, where an array of them would first set every member to its default.
template <class R>
class Unset {
 public:
  R* data() { return std::launder(reinterpret_cast<R*>(bytes_)); }
  const R* data() const { return std::launder(reinterpret_cast<const R*>(bytes_)); }
  R& operator[](int i) { return data()[i]; }
  const R& operator[](int i) const { return data()[i]; }

 private:
  alignas(R) unsigned char bytes_[sizeof(R) * kTile * kTile];
};

template <class T>
struct Surface {
  Vec<T> point{0}, normal{0};
  int material = -1;
};

template <class T>
T normal_epsilon(const MarchSettings& s, T t) {
  return T(s.normal_eps_scaled ? s.normal_eps * static_cast<double>(t) : s.normal_eps);
}

// A material's colour where it is the same at every point: its ramp's, or its own without a texture.
std::optional<glm::dvec3> uniform_color(const sdf::Scene& scene, const sdf::Material& m) {
  if (const auto ramped = sdf::ramp_color(scene, m)) return ramped;
  if (m.texture == sdf::TextureMapping::none) return m.color;
  return std::nullopt;
}

// A textured material's colour at p (outward normal n). Out of line: material_color stays small enough to inline
// where most colours are uniform (the call and the colour returned through memory were 1.5% of lee-flat's render).
__attribute__((noinline)) glm::dvec3 textured_color(const Context& ctx, const sdf::Material& m, glm::dvec3 p,
                                                    glm::dvec3 n) {
  const auto& scene = ctx.scene;
  // Looked up just below the surface, as the seed does (p - n * SURF_DIST), in world coordinates.
  const glm::dvec3 q = p + ctx.origin - n * scene.march.hit_eps;
  if (m.texture == sdf::TextureMapping::planar)
    return m.color * sample_texture(texture_path(m), q.x * m.texture_scale, q.z * m.texture_scale);
  // The seed's: polar angle from +y, then longitude, about the texture's origin (the sphere's centre).
  const glm::dvec3 r = q - m.texture_origin;
  const double u = glm::fract(std::atan2(std::sqrt(r.x * r.x + r.z * r.z), r.y) / std::numbers::pi),
               v = glm::fract(std::atan2(r.z, r.x) / (2 * std::numbers::pi));
  return m.color * sample_texture(texture_path(m), u * m.texture_scale, v * m.texture_scale);
}

glm::dvec3 material_color(const Context& ctx, int material, glm::dvec3 p, glm::dvec3 n) {
  if (material < 0) return glm::dvec3(0.8);
  if (const auto& uniform = ctx.uniform_colors[static_cast<size_t>(material)]) return *uniform;
  return textured_color(ctx, ctx.scene.materials[static_cast<size_t>(material)], p, n);
}

// Surface points to light together (structure of arrays), up to N: position, unit normal, eye, albedo, ambient
// occlusion, material and the shadow stage's visibility of each light (1 where the light casts no shadow).
// S: the arithmetic, float for images (ShadePrecision).
template <class S, int N>
struct LitPoints {
  int n = 0;
  alignas(64) S px[N], py[N], pz[N], nx[N], ny[N], nz[N], ex[N], ey[N], ez[N], ar[N], ag[N], ab[N], ao[N];
  int material[N];
  const double* visibility[N];
  alignas(64) S r[N], g[N], b[N];  // the colour, from direct_light
  void add(glm::vec<3, S> p, glm::vec<3, S> normal, glm::vec<3, S> eye, glm::vec<3, S> albedo, S occlusion, int m,
           const double* lights_visible) {
    px[n] = p.x, py[n] = p.y, pz[n] = p.z, nx[n] = normal.x, ny[n] = normal.y, nz[n] = normal.z;
    ex[n] = eye.x, ey[n] = eye.y, ez[n] = eye.z, ar[n] = albedo.x, ag[n] = albedo.y, ab[n] = albedo.z;
    ao[n] = occlusion, material[n] = m, visibility[n] = lights_visible;
    ++n;
  }
};

// Direct lighting of the points: diffuse variants, toon bands, specular. Loops over the points, branch-free and
// vectorised but for the specular power (a library call), with glm's expressions spelled out in glm's order.
template <class S, int N>
void direct_light(const Context& ctx, LitPoints<S, N>& in) {
  const auto& effects = ctx.scene.effects;
  const int n = in.n;
  auto dot = [](S ax, S ay, S az, S bx, S by, S bz) { return ax * bx + ay * by + az * bz; };
  // An eye on the surface point (a miss read as a hit at the ray origin) has no direction: face the normal.
  alignas(64) S tx[N], ty[N], tz[N];
  for (int i = 0; i < n; ++i) {
    const S dx = in.ex[i] - in.px[i], dy = in.ey[i] - in.py[i], dz = in.ez[i] - in.pz[i];
    const S d2 = dot(dx, dy, dz, dx, dy, dz);
    const S inv = S(1) / std::sqrt(d2);  // glm::normalize
    const bool away = d2 > 0;             // glm::length(d) > 0
    tx[i] = away ? dx * inv : in.nx[i];
    ty[i] = away ? dy * inv : in.ny[i];
    tz[i] = away ? dz * inv : in.nz[i];
  }
  const S ambient = S(effects.ambient);
  for (int i = 0; i < n; ++i) {
    in.r[i] = in.ar[i] * ambient * in.ao[i];
    in.g[i] = in.ag[i] * ambient * in.ao[i];
    in.b[i] = in.ab[i] * ambient * in.ao[i];
  }
  // Each point's specular model (0 none, 1 Phong, 2 Blinn-Phong), strength and shininess.
  alignas(64) S model[N]{}, strength[N]{}, shininess[N]{};  // zeroed: GCC cannot see n <= N for N = 1
  bool any_blinn = false;
  for (int i = 0; i < n; ++i) {
    const sdf::Material* m = in.material[i] >= 0 ? &ctx.scene.materials[static_cast<size_t>(in.material[i])] : nullptr;
    const auto kind = m ? m->specular : sdf::SpecularModel::none;
    model[i] = kind == sdf::SpecularModel::none ? S(0) : kind == sdf::SpecularModel::phong ? S(1) : S(2);
    any_blinn = any_blinn || model[i] == S(2);
    strength[i] = m ? S(m->specular_strength) : S(0);
    shininess[i] = m ? S(m->shininess) : S(1);
  }
  const bool toon = effects.shading == sdf::Shading::toon;
  const S bands = S(effects.toon_bands);
  // The seed's bands: mix(0.1, 1, mod(floor(bands x), bands) / (bands - 1)), so x = 1 falls in the lowest band.
  auto quantise = [&](S x) {
    const S scaled = std::floor(std::clamp(x, S(0), S(1)) * bands), band = scaled == bands ? S(0) : scaled;
    return glm::mix(S(0.1), S(1), band / (bands - 1));
  };
  // Per-scene choices made outside the loops.
  const bool clamped = effects.diffuse != sdf::Diffuse::unclamped;
  const S floor = effects.diffuse == sdf::Diffuse::floor ? S(effects.diffuse_floor) : S(0);
  for (size_t li = 0; li < ctx.scene.lights.size(); ++li) {
    const auto& light = ctx.scene.lights[li];
    const glm::vec<3, S> at(ctx.light_positions[li]), toward = -glm::normalize(glm::vec<3, S>(light.direction));
    const glm::vec<3, S> color(light.color);
    const S darkening = S(light.darkening);
    const bool specular_kept = light.specular_in_shadow;
    alignas(64) S diffuse[N], base[N], specular[N], visible[N], lx[N], ly[N], lz[N];  // l: toward the light
    for (int i = 0; i < n; ++i) visible[i] = S(in.visibility[i][li]);
    auto lambert_and_phong = [&](auto point_light) {
      for (int i = 0; i < n; ++i) {
        lx[i] = toward.x, ly[i] = toward.y, lz[i] = toward.z;
        if constexpr (point_light) {
          const S dx = at.x - in.px[i], dy = at.y - in.py[i], dz = at.z - in.pz[i];
          const S inv = S(1) / std::sqrt(dot(dx, dy, dz, dx, dy, dz));
          lx[i] = dx * inv, ly[i] = dy * inv, lz[i] = dz * inv;
        }
        const S cosine = dot(in.nx[i], in.ny[i], in.nz[i], lx[i], ly[i], lz[i]);
        diffuse[i] = clamped ? std::clamp(cosine, floor, S(1)) : cosine;
        // Phong: dot(reflect(-l, n), to_eye), reflect(I, N) = I - N * dot(N, I) * 2.
        const S d = dot(in.nx[i], in.ny[i], in.nz[i], -lx[i], -ly[i], -lz[i]);
        const S rx = -lx[i] - in.nx[i] * d * S(2), ry = -ly[i] - in.ny[i] * d * S(2), rz = -lz[i] - in.nz[i] * d * S(2);
        base[i] = dot(rx, ry, rz, tx[i], ty[i], tz[i]);
      }
    };
    if (light.type == sdf::LightType::point) {
      lambert_and_phong(std::true_type{});
    } else {
      lambert_and_phong(std::false_type{});
    }
    if (any_blinn)
      for (int i = 0; i < n; ++i) {
        if (model[i] != S(2)) continue;
        const glm::vec<3, S> h = glm::normalize(glm::vec<3, S>(lx[i], ly[i], lz[i]) + glm::vec<3, S>(tx[i], ty[i], tz[i]));
        base[i] = dot(in.nx[i], in.ny[i], in.nz[i], h.x, h.y, h.z);
      }
    for (int i = 0; i < n; ++i)
      specular[i] = model[i] == S(0) ? S(0) : strength[i] * std::pow(std::clamp(base[i], S(0), S(1)), shininess[i]);
    if (toon)
      for (int i = 0; i < n; ++i) {
        diffuse[i] = quantise(diffuse[i]);
        specular[i] = model[i] != S(0) ? std::min(quantise(specular[i]), diffuse[i]) : S(0);
      }
    for (int i = 0; i < n; ++i) {
      const S v = visible[i], shade = glm::mix(darkening, S(1), v), lit = specular[i] * (specular_kept ? S(1) : v);
      in.r[i] += color.x * (in.ar[i] * diffuse[i] * shade + lit);
      in.g[i] += color.y * (in.ag[i] * diffuse[i] * shade + lit);
      in.b[i] += color.z * (in.ab[i] * diffuse[i] * shade + lit);
    }
  }
  if (toon)
    for (int i = 0; i < n; ++i)
      if (dot(tx[i], ty[i], tz[i], in.nx[i], in.ny[i], in.nz[i]) < S(effects.silhouette)) in.r[i] = in.g[i] = in.b[i] = 0;
}

constexpr size_t kMaxLights = 16;

// Unit direction from p toward a light, and its distance (infinite for a directional light).
template <class T>
std::pair<Vec<T>, T> toward_light(const sdf::Light& light, glm::dvec3 position, Vec<T> p) {
  if (light.type != sdf::LightType::point)
    return {-glm::normalize(Vec<T>(light.direction)), std::numeric_limits<T>::infinity()};
  const Vec<T> d = Vec<T>(position) - p;
  const T dist = glm::length(d);
  return {d / dist, dist};
}

template <class T>
struct Tracer {
  const Context& ctx;
  Counters& counters;

  // Marches and shades a secondary ray (reflection or refraction), charging all its evaluations to stage.
  glm::dvec3 trace(Vec<T> origin, Vec<T> dir, int depth, Stage stage) {
    const auto& s = ctx.scene.march;
    const TapeField field{&ctx.tape};
    const auto r = march<T>(field, origin, dir, s, ctx.march);
    auto& cost = counters.stages[stage];
    cost.evals += static_cast<std::uint64_t>(r.evals);
    if (r.outcome != Outcome::hit) return ctx.scene.effects.background;
    const Vec<T> p = origin + dir * r.t;
    const auto n = estimate_normal(field, p, s.normal, normal_epsilon(s, r.t));
    const int material = sdf::sample(ctx.tape, p).material;
    cost.evals += static_cast<std::uint64_t>(n.evals + 1);
    double visibility[kMaxLights];
    cost.evals += shadows(p, n.n, r.t, visibility);
    const glm::dvec3 pd(p), nd(n.n);
    LitPoints<double, 1> lit;
    lit.add(pd, nd, glm::dvec3(origin), material_color(ctx, material, pd, nd), 1.0, material, visibility);
    direct_light(ctx, lit);
    return bounce(glm::dvec3(lit.r[0], lit.g[0], lit.b[0]), p, n.n, dir, material, depth, r.t);
  }

  // The reference's shadows at its point p (in the march's coordinates; outward normal n): each light's ray starts
  // lift off the surface along n, lift bounding how far p may lie from the surface, so that it starts outside the
  // solid it leaves.
  void reference_shadows(glm::dvec3 p, glm::dvec3 n, double lift, double* visibility) const {
    for (size_t i = 0; i < ctx.scene.lights.size(); ++i) {
      const auto& light = ctx.scene.lights[i];
      visibility[i] = 1;
      if (light.shadow == sdf::ShadowMode::none) continue;
      const glm::dvec3 lp = ctx.light_positions[i];
      const bool point = light.type == sdf::LightType::point;
      const glm::dvec3 l = point ? glm::normalize(lp - p) : -glm::normalize(light.direction);
      visibility[i] = ctx.oracle->first_hit(p + ctx.origin + n * lift, l, point ? glm::length(lp - p) : 1e9) ? 0.0 : 1.0;
    }
  }

  // Fills the visibility of every light; returns the evaluations spent.
  std::uint64_t shadows(Vec<T> p, Vec<T> n, T t, double* visibility) {
    const TapeField field{&ctx.tape};
    std::uint64_t evals = 0;
    if (ctx.oracle) {  // a point found in T (a triangle mesh's): lifted by T's rounding of it
      const glm::dvec3 pd(p);
      reference_shadows(pd, glm::dvec3(n), tolerance::shadow_lift(pd), visibility);
      return 0;
    }
    for (size_t i = 0; i < ctx.scene.lights.size(); ++i) {
      const auto& light = ctx.scene.lights[i];
      visibility[i] = 1;
      if (light.shadow == sdf::ShadowMode::none) continue;
      const auto [to_light, dist] = toward_light(light, ctx.light_positions[i], p);
      const auto sv = shadow_visibility<T>(field, p, n, to_light, dist, t, light, ctx.scene.march, ctx.march);
      visibility[i] = sv.visibility;
      evals += static_cast<std::uint64_t>(sv.evals);
    }
    return evals;
  }

  // Mixes in mirror reflection and refraction (Schlick-weighted) for materials that declare them. The
  // primary bounce (depth 0) books the time of each kind; deeper bounces are inside that time.
  glm::dvec3 bounce(glm::dvec3 local, Vec<T> p, Vec<T> n, Vec<T> dir, int material, int depth, T t) {
    if (material < 0 || depth >= ctx.scene.effects.max_bounces) return local;
    const auto& m = ctx.scene.materials[static_cast<size_t>(material)];
    if (m.reflectivity <= 0 && m.transparency <= 0) return local;
    auto timed = [&](Stage stage, auto&& fn) {
      if (depth > 0) return fn();
      const auto start = Clock::now();
      const glm::dvec3 c = fn();
      counters.stages[stage].seconds += since(start);
      return c;
    };
    const T offset = T(2) * hit_threshold(ctx.scene.march, ctx.march, t) + T(1e-4);
    const glm::dvec3 reflected =
        timed(kReflection, [&] { return trace(p + n * offset, glm::reflect(dir, n), depth + 1, kReflection); });
    glm::dvec3 color = glm::mix(local, reflected, m.reflectivity);
    if (m.transparency > 0) {
      const glm::dvec3 refracted = timed(kRefraction, [&] {
        const TapeField field{&ctx.tape};
        const auto through = refract_through<T>(field, p, n, dir, m.ior, ctx.scene.march, ctx.march,
                                               normal_epsilon(ctx.scene.march, t));
        counters.stages[kRefraction].evals += static_cast<std::uint64_t>(through.evals);
        return through.ok ? trace(through.exit_point, through.exit_direction, depth + 1, kRefraction)
                          : ctx.scene.effects.background;
      });
      const double fresnel = schlick_fresnel(-glm::dot(glm::dvec3(dir), glm::dvec3(n)), 1.0, m.ior);
      color = glm::mix(color, fresnel * reflected + (1 - fresnel) * refracted, m.transparency);
    }
    return color;
  }
};

// One tile's pixels through the stages the scene declares, each stage one pass over the tile (its rays in packets
// through the batched tape where it can), timed and charged with its evaluations. The surfaces come from one of
// two sources: the marcher, or the reference (a SurfaceOracle) for reference renders.
template <class T>
class TileRenderer {
 public:
  TileRenderer(const Context& ctx, int x0, int y0, RenderResult& out, Counters& counters)
      : ctx_(ctx), s_(ctx.scene.march), effects_(ctx.scene.effects), pipe_(ctx.pipeline), out_(out),
        counters_(counters), tracer_{ctx, counters}, x0_(x0), y0_(y0), x1_(std::min(x0 + kTile, out.color.width)),
        y1_(std::min(y0 + kTile, out.color.height)), w_(x1_ - x0_), pixels_(w_ * (y1_ - y0_)),
        per_pixel_cost_(!out.evals.pixels.empty() || !out.stage_evals.pixels.empty()),
        more_images_(per_pixel_cost_ || !out.depth.pixels.empty() || !out.normal.pixels.empty() ||
                     !out.steps.pixels.empty() || !out.id.pixels.empty() || !out.outcome.pixels.empty()),
        lights_(ctx.scene.lights.size()) {
    if (per_pixel_cost_) cost_.fill({});
    std::fill_n(visibility_, pixels_ * lights_, 1.0);  // until the shadow stage finds otherwise
  }

  void run() {
    make_rays();
    if (ctx_.meshes) intersect_meshes();
    if (ctx_.oracle) {
      reference_surfaces();
    } else {
      marched_surfaces();
    }
    // In a local, not through the counters at every pixel (a chain of loads and stores, 16% of shade's samples).
    int steps_max = 0;
    for (int k = 0; k < pixels_; ++k) steps_max = std::max(steps_max, records_[k].steps);
    counters_.steps_max = std::max(counters_.steps_max, steps_max);
    if (pipe_.normals && !ctx_.oracle) normals();
    if (pipe_.materials) materials();
    if (pipe_.shadows) shadows();
    if (pipe_.ao_samples) ambient_occlusion();
    if (ctx_.shade == ShadePrecision::float64) {
      shade(0.0);
    } else {
      shade(0.0f);
    }
    // Secondary rays run inside the shading loop and book their own time: take it out of shading's.
    lap(kShade);
    counters_.stages[kShade].seconds -= bounce_seconds_;
  }

 private:
  using V = Vec<T>;
  // A pixel's surface; its ray and its march's record are beside it (rays_, records_).
  struct PixelState {
    V point{0};  // the surface point, origin + direction t, once the surface is known
    V normal{0};
    int material = -1;
    double ao = 1;
    bool hit = false;
    bool on_mesh = false;  // the nearest surface is a triangle mesh, not the field
  };
  // Reference renders: the oracle's hit in double, at origin + unit direction t, within lift of the surface (its
  // shadow rays start there, not at the float point, which can lie deeper inside).
  struct ReferenceHit {
    double t, lift;
  };
  // Beside the pixels rather than in them, so that the tile's state stays in the first-level cache: the
  // evaluations per pixel (all stages, then each), kept only for the images that show them.
  struct PixelCost {
    std::uint64_t evals;
    std::array<std::uint64_t, kStageCount> stages;
  };

  // fn(pixel, k) for the tile's pixels in row order, k the pixel's index in the tile.
  template <class Fn>
  void each(Fn&& fn) {
    for (int k = 0; k < pixels_; ++k) fn(px_[static_cast<size_t>(k)], k);
  }
  // Books a pass of a stage: its time as a lap (each stage's end is the next one's start: one clock reading per pass,
  // not two), and the evaluations it spent, added up in a local by charge.
  void lap(Stage which, std::uint64_t spent = 0) {
    const auto now = Clock::now();
    counters_.stages[which].seconds += std::chrono::duration<double>(now - mark_).count();
    counters_.stages[which].evals += spent;
    mark_ = now;
  }
  // Books evaluations a stage spent on pixel k: to the pixel where its cost images are kept, and to `spent`, the pass's
  // local sum that lap books (added to the counters at every pixel, it was a chain of loads and stores: the pixels'
  // counts are of the same type, so the compiler could not keep it in a register).
  void charge(Stage which, int k, std::uint64_t evals, std::uint64_t& spent) {
    if (per_pixel_cost_) {
      auto& c = cost_[static_cast<size_t>(k)];
      c.evals += evals;
      c.stages[which] += evals;
    }
    spent += evals;
  }
  // Runs one stage over the tile, timing it and charging the evaluations it reports.
  template <class Fn>
  void stage(Stage which, Fn&& fn) {
    std::uint64_t spent = 0;
    each([&](PixelState& p, int k) { charge(which, k, static_cast<std::uint64_t>(fn(p, k)), spent); });
    lap(which, spent);
  }
  double* visibility(int k) { return visibility_ + static_cast<size_t>(k) * lights_; }
  bool surface(const PixelState& p) const { return p.hit || p.on_mesh; }
  // The meshes' hit along the pixel's ray; none where the scene has no mesh.
  const MeshHit* mesh(int k) {
    return ctx_.meshes && meshes_[k].hit ? &meshes_[k] : nullptr;
  }
  // The ray's direction in double, unit length, as the oracle is asked along it (its t is along this).
  glm::dvec3 unit_direction(int k) const {
    return glm::dvec3(rays_[k].direction) / glm::length(glm::dvec3(rays_[k].direction));
  }

  // The camera's rays, for every pixel at once (bit for bit the ray of each pixel), charged to the march.
  void make_rays() {
    double xs[kTile * kTile], ys[kTile * kTile];
    for (int y = y0_, k = 0; y < y1_; ++y)
      for (int x = x0_; x < x1_; ++x, ++k) {
        xs[k] = x + 0.5;
        ys[k] = y + 0.5;
      }
    ctx_.camera.rays(xs, ys, pixels_, camera_rays_);
    for (int k = 0; k < pixels_; ++k)
      rays_[k] = {V(camera_rays_[k].origin - ctx_.origin), V(camera_rays_[k].direction), s_.max_dist};
    lap(kMarch);
  }

  // Meshes are intersected along the camera's rays in double, before any rounding to T.
  void intersect_meshes() {
    stage(kMesh, [&](PixelState&, int k) {
      const Ray& ray = camera_rays_[k];
      meshes_[k] = ctx_.meshes->intersect(ray.origin, ray.direction, s_.max_dist);
      if (meshes_[k].hit) rays_[k].max_dist = meshes_[k].t;  // the march stops at the mesh
      return 0;
    });
  }

  // The nearest surface is a mesh's where the mesh is nearer than the field's, or the field has none.
  void take_mesh(PixelState& p, int k, const MeshHit& mesh) {
    p.on_mesh = true;
    records_[k].t = static_cast<T>(mesh.t);
    p.normal = V(mesh.normal);
    p.material = mesh.material;
  }
  void surface_found(PixelState& p, int k) { p.point = rays_[k].origin + rays_[k].direction * records_[k].t; }

  // Surface source one: the marcher, every ray of the tile in one packet. The march stops at the mesh, as the
  // seed's does at the depth buffer's distance.
  void marched_surfaces() {
    march_packet(ctx_.tape, rays_, records_.data(), pixels_, s_, ctx_.march);
    stage(kMarch, [&](PixelState& p, int k) {
      const bool field_hit = records_[k].outcome == Outcome::hit;  // as marched, before the scene's reading
      records_[k] = as_read(records_[k], s_);
      p.hit = records_[k].outcome == Outcome::hit;
      if (const MeshHit* on = mesh(k); on && !field_hit) take_mesh(p, k, *on);
      surface_found(p, k);
      return records_[k].evals;
    });
  }

  // Surface source two: the reference's first hit along each ray, with its exact normal.
  void reference_surfaces() {
    stage(kMarch, [&](PixelState& p, int k) {
      const double len = glm::length(glm::dvec3(rays_[k].direction));
      const glm::dvec3 origin = glm::dvec3(rays_[k].origin) + ctx_.origin;  // the oracle's world
      const auto hit = ctx_.oracle->first_hit(origin, unit_direction(k), s_.max_dist);
      records_[k] = {};
      records_[k].outcome = hit ? Outcome::hit : Outcome::miss_far;
      records_[k].t = hit ? static_cast<T>(hit->t / len) : T(0);
      if (hit) {
        p.normal = V(hit->normal);
        references_[k] = {hit->t, tolerance::reference_hit_slack(origin, hit->t, hit->t_error)};
      }
      p.hit = hit.has_value();
      if (const MeshHit* on = mesh(k); on && (!hit || on->t < hit->t / len)) {
        p.hit = false;
        take_mesh(p, k, *on);
      }
      surface_found(p, k);
      return 0;
    });
  }

  void normals() {
    if (s_.normal != NormalMethod::central) {  // the others stay one point at a time
      const TapeField field{&ctx_.tape};
      stage(kNormal, [&](PixelState& p, int k) {
        if (!p.hit) return 0;
        const auto n = estimate_normal(field, p.point, s_.normal, normal_epsilon(s_, records_[k].t));
        p.normal = n.n;
        return n.evals;
      });
      return;
    }
    // Zeroed: GCC without -march=native cannot see that the first count entries are written before the call.
    V points[kTile * kTile] = {};
    T eps[kTile * kTile] = {};
    int which[kTile * kTile];
    Unset<NormalResult<T>> normals;
    int count = 0;
    each([&](PixelState& p, int k) {
      if (!p.hit) return;
      points[count] = p.point;
      eps[count] = normal_epsilon(s_, records_[k].t);
      which[count++] = k;
    });
    central_normals_packet(ctx_.tape, points, eps, normals.data(), count);
    std::uint64_t spent = 0;
    for (int i = 0; i < count; ++i) {
      px_[static_cast<size_t>(which[i])].normal = normals[i].n;
      charge(kNormal, which[i], static_cast<std::uint64_t>(normals[i].evals), spent);
    }
    lap(kNormal, spent);
  }

  void materials() {
    alignas(64) T xs[kTile * kTile], ys[kTile * kTile], zs[kTile * kTile], values[kTile * kTile];
    int materials[kTile * kTile], which[kTile * kTile];
    int count = 0;
    each([&](PixelState& p, int k) {
      if (!p.hit) return;
      xs[count] = p.point.x;
      ys[count] = p.point.y;
      zs[count] = p.point.z;
      which[count++] = k;
    });
    for (int b = 0; b < count; b += sdf::kBatch)
      sdf::sample_batch(ctx_.tape, xs + b, ys + b, zs + b, values + b, materials + b, std::min(sdf::kBatch, count - b));
    std::uint64_t spent = 0;
    for (int i = 0; i < count; ++i) {
      px_[static_cast<size_t>(which[i])].material = materials[i];
      charge(kMaterial, which[i], 1, spent);
    }
    lap(kMaterial, spent);
  }

  // Hard shadows march in packets, one per light; soft ones (and the reference's) one ray at a time.
  void shadows() {
    bool batched = !ctx_.oracle;
    for (const auto& light : ctx_.scene.lights) batched = batched && light.shadow != sdf::ShadowMode::soft;
    if (!batched) {
      stage(kShadow, [&](PixelState& p, int k) {
        if (!surface(p)) return std::uint64_t{0};
        if (!ctx_.oracle || !p.hit) return tracer_.shadows(p.point, p.normal, records_[k].t, visibility(k));
        const ReferenceHit& reference = references_[k];
        tracer_.reference_shadows(glm::dvec3(rays_[k].origin) + unit_direction(k) * reference.t, glm::dvec3(p.normal),
                                  reference.lift, visibility(k));
        return std::uint64_t{0};
      });
      return;
    }
    PacketRay<T> rays[kTile * kTile];
    ShadowStart<T> starts[kTile * kTile];
    Unset<RayRecord<T>> records;
    int which[kTile * kTile];
    std::uint64_t spent = 0;
    for (size_t li = 0; li < lights_; ++li) {
      const auto& light = ctx_.scene.lights[li];
      if (light.shadow == sdf::ShadowMode::none) continue;
      int count = 0;
      each([&](PixelState& p, int k) {
        if (!surface(p)) return;
        const auto [to_light, dist] = toward_light(light, ctx_.light_positions[li], p.point);
        starts[count] = shadow_start(p.point, p.normal, dist, records_[k].t, light, s_, ctx_.march);
        rays[count] = {starts[count].origin, to_light, starts[count].max_dist};
        which[count++] = k;
      });
      march_packet(ctx_.tape, rays, records.data(), count, s_, ctx_.march);
      for (int i = 0; i < count; ++i) {
        visibility(which[i])[li] = hard_visibility(records[i], starts[i], light);
        charge(kShadow, which[i], static_cast<std::uint64_t>(records[i].evals), spent);
      }
    }
    lap(kShadow, spent);
  }

  void ambient_occlusion() {
    const TapeField field{&ctx_.tape};
    stage(kAo, [&](PixelState& p, int) {
      if (!p.hit) return 0;
      double occlusion = 0, weights = 0, weight = 1;
      for (int i = 1; i <= effects_.ao_samples; ++i) {
        const T h = T(effects_.ao_distance * i / effects_.ao_samples);
        const double d = static_cast<double>(field(p.point + p.normal * h));
        occlusion += weight * std::clamp((static_cast<double>(h) - d) / static_cast<double>(h), 0.0, 1.0);
        weights += weight;
        weight *= 0.85;
      }
      p.ao = 1 - occlusion / weights;
      return effects_.ao_samples;
    });
  }

  // Shading and secondary rays work in double from the ray: the surface point as double computes it.
  glm::dvec3 point_in_double(int k) const {
    return glm::dvec3(rays_[k].origin) + glm::dvec3(rays_[k].direction) * static_cast<double>(records_[k].t);
  }

  // The tile's colours in arithmetic S (the type of `zero`): its surface pixels lit together in chunks of 64 (so
  // that the lit points stay beside the tile's state in the first-level cache), then each pixel finished.
  // Kept out of line: inlined, it made GCC compile the marching stages above 10% slower.
  template <class S>
  __attribute__((noinline)) void shade(S) {
    using VS = glm::vec<3, S>;
    constexpr int kChunk = 64;
    LitPoints<S, kChunk> lit;
    int lit_index[kChunk];
    const bool lighting = !(ctx_.scene.lights.empty() && !pipe_.materials);
    for (int first = 0; first < pixels_; first += kChunk) {
      const int last = std::min(first + kChunk, pixels_);
      lit.n = 0;
      for (int k = first; k < last; ++k) {
        PixelState& p = px_[static_cast<size_t>(k)];
        lit_index[k - first] = -1;
        if (!surface(p) || !lighting) continue;
        const glm::dvec3 at = point_in_double(k);
        const VS n(p.normal);
        const VS eye = effects_.eye_is_ray_direction && !ctx_.oracle ? VS(rays_[k].direction) : VS(rays_[k].origin);
        const VS albedo =
            pipe_.materials || p.on_mesh ? VS(material_color(ctx_, p.material, at, glm::dvec3(n))) : VS(S(0.8));
        lit_index[k - first] = lit.n;
        lit.add(VS(at), n, eye, albedo, S(p.ao), p.material, visibility(k));
      }
      direct_light(ctx_, lit);
      for (int k = first, x = x0_ + first % w_, y = y0_ + first / w_; k < last; ++k) {
        PixelState& p = px_[static_cast<size_t>(k)];
        const int at = lit_index[k - first];
        const VS color = finish(p, k, at >= 0 ? VS(lit.r[at], lit.g[at], lit.b[at]) : VS(0));
        write(p, k, x, y, glm::dvec3(color));
        if (++x == x1_) x = x0_, ++y;
      }
    }
  }

  // One pixel's colour from its direct light: step-count occlusion, secondary rays, fog; glow on misses.
  template <class VS>
  VS finish(PixelState& p, int k, VS color) {
    using S = typename VS::value_type;
    if (!surface(p)) {
      color = VS(effects_.background);
      if (effects_.glow > 0 && !ctx_.oracle) {
        const S g = std::clamp(S(1) - static_cast<S>(records_[k].min_abs_f) / S(effects_.glow_width), S(0), S(1));
        color += VS(effects_.glow_color) * (S(effects_.glow) * g * g);
      }
      return color;
    }
    if (effects_.ao == sdf::AmbientOcclusion::steps && !ctx_.oracle)
      color -= VS(S(static_cast<double>(records_[k].steps) * records_[k].steps * effects_.ao_steps_scale));
    if (pipe_.reflection || pipe_.refraction) color = VS(bounce(p, k, glm::dvec3(color)));
    color = glm::max(color, VS(0));
    if (effects_.fog > 0)
      color = glm::mix(VS(effects_.fog_color), color, S(std::exp(-effects_.fog * static_cast<double>(records_[k].t))));
    return color;
  }

  // Mirror and refraction rays from the pixel's surface, timed apart from shading and charged to the pixel.
  glm::dvec3 bounce(const PixelState& p, int k, glm::dvec3 local) {
    const auto start = Clock::now();
    const std::uint64_t reflection = counters_.stages[kReflection].evals;
    const std::uint64_t refraction = counters_.stages[kRefraction].evals;
    const glm::dvec3 color =
        tracer_.bounce(local, V(point_in_double(k)), p.normal, rays_[k].direction, p.material, 0, records_[k].t);
    if (per_pixel_cost_) {
      auto& c = cost_[static_cast<size_t>(k)];
      c.stages[kReflection] += counters_.stages[kReflection].evals - reflection;
      c.stages[kRefraction] += counters_.stages[kRefraction].evals - refraction;
      c.evals += c.stages[kReflection] + c.stages[kRefraction];
    }
    bounce_seconds_ += since(start);
    return color;
  }

  // Pixel k's (at x, y) colour and the images kept (the others are empty: render's `images`).
  void write(const PixelState& p, int k, int x, int y, glm::dvec3 color) {
    float* c = out_.color.at(x, y);
    for (int i = 0; i < 3; ++i) c[i] = static_cast<float>(color[i]);
    if (!more_images_) return;
    if (!out_.depth.pixels.empty()) *out_.depth.at(x, y) = surface(p) ? static_cast<float>(records_[k].t) : INFINITY;
    if (!out_.normal.pixels.empty()) {
      float* n = out_.normal.at(x, y);
      for (int i = 0; i < 3; ++i) n[i] = static_cast<float>(p.normal[i]);
    }
    if (!out_.steps.pixels.empty()) *out_.steps.at(x, y) = static_cast<float>(records_[k].steps);
    const PixelCost& pc = cost_[static_cast<size_t>(k)];
    if (!out_.evals.pixels.empty()) *out_.evals.at(x, y) = static_cast<float>(pc.evals);
    if (!out_.stage_evals.pixels.empty())
      for (int i = 0; i < kStageCount; ++i) out_.stage_evals.at(x, y)[i] = static_cast<float>(pc.stages[static_cast<size_t>(i)]);
    if (!out_.id.pixels.empty()) *out_.id.at(x, y) = static_cast<float>(p.material);
    if (!out_.outcome.pixels.empty()) *out_.outcome.at(x, y) = static_cast<float>(records_[k].outcome);
  }

  const Context& ctx_;
  const MarchSettings& s_;
  const sdf::Effects& effects_;
  const Pipeline& pipe_;
  RenderResult& out_;
  Counters& counters_;
  Tracer<T> tracer_;
  const int x0_, y0_, x1_, y1_, w_, pixels_;
  const bool per_pixel_cost_;
  // Any image besides the colour (the render command's usual case has none): checked once a pixel, not once an image.
  const bool more_images_;
  const size_t lights_;
  std::array<PixelState, kTile * kTile> px_;
  // Beside the pixels, set and read only where the scene has meshes or the surfaces are the reference's.
  Unset<MeshHit> meshes_;
  Unset<ReferenceHit> references_;
  Unset<RayRecord<T>> records_;  // the march's (its reading), or the reference's
  Ray camera_rays_[kTile * kTile];  // in double, in world coordinates
  // As the march takes them: relative to the march's origin, in T, to the scene's max_dist or the mesh's hit.
  PacketRay<T> rays_[kTile * kTile];
  std::array<PixelCost, kTile * kTile> cost_;
  double visibility_[kTile * kTile * kMaxLights];  // lights_ entries per pixel
  Clock::time_point mark_ = Clock::now();
  double bounce_seconds_ = 0;
};

}  // namespace

RenderResult render(const sdf::Scene& scene, const std::vector<Aov>& aovs, const SurfaceOracle* oracle, Images images,
                    ShadePrecision shade) {
  const auto start = Clock::now();
  const int w = scene.width, h = scene.height;
  if (scene.lights.size() > kMaxLights) throw std::invalid_argument("at most 16 lights");
  const glm::dvec3 origin = march_origin(scene);
  Context ctx{scene,   origin, march_tape(scene, origin), Camera(scene.camera, w, h), {}, plan(scene, aovs, oracle),
              nullptr, oracle, {},     shade,  {}};
  ctx.march = march_context(ctx.camera, scene, origin);
  for (const auto& light : scene.lights) ctx.light_positions.push_back(light.position_at(scene.time) - origin);
  for (const auto& m : scene.materials) ctx.uniform_colors.push_back(uniform_color(scene, m));
  if (ctx.pipeline.textures) {
    soil_texture_path();  // made once, before the tiles look it up in parallel
    check_texture_files(scene);
  }
  if (!scene.meshes.empty()) ctx.meshes = std::make_unique<MeshOccluder>(scene.meshes);

  RenderResult out;
  out.color = Image::unset(w, h, 3);
  out.transfer = scene.output_transfer;
  auto keep = [&](Aov aov) { return images == Images::all || std::find(aovs.begin(), aovs.end(), aov) != aovs.end(); };
  if (keep(Aov::depth)) out.depth = Image::unset(w, h, 1);
  if (keep(Aov::normal)) out.normal = Image::unset(w, h, 3);
  if (keep(Aov::steps)) out.steps = Image::unset(w, h, 1);
  if (keep(Aov::evals)) out.evals = Image::unset(w, h, 1);
  if (keep(Aov::stages)) out.stage_evals = Image::unset(w, h, kStageCount);
  out.stage_names.assign(std::begin(kStageNames), std::end(kStageNames));
  if (keep(Aov::id)) out.id = Image::unset(w, h, 1);
  if (images == Images::all) out.outcome = Image::unset(w, h, 1);

  const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
  tbb::enumerable_thread_specific<Counters> counters;
  tbb::parallel_for(0, tiles_x * tiles_y, [&](int tile) {
    const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
    if (scene.march.precision == sdf::Precision::float64) {
      TileRenderer<double>(ctx, x0, y0, out, counters.local()).run();
    } else {
      TileRenderer<float>(ctx, x0, y0, out, counters.local()).run();
    }
  });
  for (int i = 0; i < kStageCount; ++i) out.stages[kStageNames[i]] = {};
  for (const auto& c : counters) {
    out.steps_max = std::max(out.steps_max, c.steps_max);
    for (int i = 0; i < kStageCount; ++i) {
      out.stages[kStageNames[i]].evals += c.stages[static_cast<size_t>(i)].evals;
      out.stages[kStageNames[i]].seconds += c.stages[static_cast<size_t>(i)].seconds;
    }
  }
  for (const auto& [name, cost] : out.stages) out.total_evals += cost.evals;
  out.seconds = since(start);
  return out;
}

bool join_render_workers() {
  tbb::task_scheduler_handle handle{tbb::attach{}};
  return tbb::finalize(handle, std::nothrow);
}

std::map<std::string, double> cost_metrics(const RenderResult& result) {
  std::map<std::string, double> m;
  for (const auto& [name, cost] : result.stages) {
    m["cost.stages." + name + ".evals"] = static_cast<double>(cost.evals);
    m["cost.stages." + name + ".seconds"] = cost.seconds;
  }
  m["cost.evals"] = static_cast<double>(result.total_evals);
  m["cost.evals_per_pixel"] = result.evals_per_pixel();
  m["cost.steps_max"] = result.steps_max;
  m["cost.seconds"] = result.seconds;
  return m;
}

}  // namespace marchcheck::march
