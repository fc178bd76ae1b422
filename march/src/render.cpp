#include "marchcheck/march/render.hpp"

#include "marchcheck/march/normals.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <sstream>
#include <stdexcept>

namespace marchcheck::march {

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
  const bool relax_ok = s.marcher != Marcher::relaxed || (s.relaxation >= 1 && s.relaxation < 2);
  const bool fixed_ok = s.marcher != Marcher::fixed || (s.fixed_step > 0 && std::isfinite(s.fixed_step));
  const bool eps_ok = s.hit_eps >= 0 && std::isfinite(s.hit_eps) && c.footprint_at_0 >= 0 && c.footprint_slope >= 0;
  return !(s.max_steps >= 0 && s.max_dist > 0 && scale_ok && lipschitz_ok && relax_ok && fixed_ok && eps_ok);
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
    else throw std::invalid_argument("unknown AOV '" + item + "'; expected depth, normal, steps, evals, id");
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
  }
  return "?";
}

double RenderResult::evals_per_pixel() const {
  const double pixels = static_cast<double>(color.width) * color.height;
  return pixels > 0 ? static_cast<double>(total_evals) / pixels : 0;
}

namespace {

enum Stage { kMarch, kNormal, kMaterial, kShade, kStageCount };
constexpr const char* kStageNames[kStageCount] = {"march", "normal", "material", "shade"};
constexpr int kTile = 16;

struct Counters {
  std::array<StageCost, kStageCount> stages{};
};

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct Context {
  const sdf::Scene& scene;
  sdf::Tape tape;
  Camera camera;
  MarchContext march;
};

template <class T>
void render_tile(const Context& ctx, int x0, int y0, RenderResult& out, Counters& counters) {
  using V = glm::vec<3, T>;
  const auto& s = ctx.scene.march;
  const TapeField field{&ctx.tape};
  const int x1 = std::min(x0 + kTile, out.color.width), y1 = std::min(y0 + kTile, out.color.height);
  struct PixelState {
    V origin, direction;
    RayRecord<T> record;
    V normal{0};
    int material = -1;
    int evals = 0;
  };
  std::array<PixelState, kTile * kTile> px;
  const int w = x1 - x0;
  auto each = [&](auto&& fn) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) fn(px[static_cast<size_t>((y - y0) * w + (x - x0))], x, y);
  };

  auto start = Clock::now();
  each([&](PixelState& p, int x, int y) {
    const Ray ray = ctx.camera.ray(x + 0.5, y + 0.5);
    p.origin = V(ray.origin);
    p.direction = V(ray.direction);
    p.record = march<T>(field, p.origin, p.direction, s, ctx.march);
    p.evals = p.record.evals;
    counters.stages[kMarch].evals += static_cast<std::uint64_t>(p.record.evals);
  });
  counters.stages[kMarch].seconds += since(start);

  start = Clock::now();
  each([&](PixelState& p, int, int) {
    if (p.record.outcome != Outcome::hit) return;
    const V hit = p.origin + p.direction * p.record.t;
    const T eps = T(s.normal_eps_scaled ? s.normal_eps * static_cast<double>(p.record.t) : s.normal_eps);
    const auto n = estimate_normal(field, hit, s.normal, eps);
    p.normal = n.n;
    p.evals += n.evals;
    counters.stages[kNormal].evals += static_cast<std::uint64_t>(n.evals);
  });
  counters.stages[kNormal].seconds += since(start);

  start = Clock::now();
  each([&](PixelState& p, int, int) {
    if (p.record.outcome != Outcome::hit) return;
    p.material = sdf::sample(ctx.tape, V(p.origin + p.direction * p.record.t)).material;
    p.evals += 1;
    counters.stages[kMaterial].evals += 1;
  });
  counters.stages[kMaterial].seconds += since(start);

  start = Clock::now();
  const auto& fx = ctx.scene.effects;
  each([&](PixelState& p, int x, int y) {
    glm::dvec3 color = fx.background;
    if (p.record.outcome == Outcome::hit) {
      const glm::dvec3 hit = glm::dvec3(p.origin) + glm::dvec3(p.direction) * static_cast<double>(p.record.t);
      const glm::dvec3 n(p.normal);
      const glm::dvec3 albedo = p.material >= 0 ? ctx.scene.materials[static_cast<size_t>(p.material)].color
                                                : glm::dvec3(0.8);
      color = albedo * fx.ambient;
      for (const auto& light : ctx.scene.lights) {
        const glm::dvec3 l = light.type == sdf::LightType::point ? glm::normalize(light.position - hit)
                                                                 : -glm::normalize(light.direction);
        color += albedo * light.color * std::clamp(glm::dot(n, l), 0.0, 1.0);
      }
    }
    float* c = out.color.at(x, y);
    for (int i = 0; i < 3; ++i) c[i] = static_cast<float>(color[i]);
    const bool hit = p.record.outcome == Outcome::hit;
    *out.depth.at(x, y) = hit ? static_cast<float>(p.record.t) : INFINITY;
    float* n = out.normal.at(x, y);
    for (int i = 0; i < 3; ++i) n[i] = static_cast<float>(p.normal[i]);
    *out.steps.at(x, y) = static_cast<float>(p.record.steps);
    *out.evals.at(x, y) = static_cast<float>(p.evals);
    *out.id.at(x, y) = static_cast<float>(p.material);
    *out.outcome.at(x, y) = static_cast<float>(p.record.outcome);
  });
  counters.stages[kShade].seconds += since(start);
}

}  // namespace

RenderResult render(const sdf::Scene& scene) {
  const auto start = Clock::now();
  const int w = scene.width, h = scene.height;
  Context ctx{scene, sdf::compile(scene.root, scene.time), Camera(scene.camera, w, h), {}};
  ctx.march.lipschitz = sdf::derive_info(scene.root, scene.time).lipschitz;
  ctx.march.footprint_at_0 = ctx.camera.footprint_at_0();
  ctx.march.footprint_slope = ctx.camera.footprint_slope();

  RenderResult out;
  out.color = Image(w, h, 3);
  out.depth = Image(w, h, 1);
  out.normal = Image(w, h, 3);
  out.steps = Image(w, h, 1);
  out.evals = Image(w, h, 1);
  out.id = Image(w, h, 1);
  out.outcome = Image(w, h, 1);

  const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
  tbb::enumerable_thread_specific<Counters> counters;
  tbb::parallel_for(0, tiles_x * tiles_y, [&](int tile) {
    const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
    if (scene.march.precision == sdf::Precision::dual) {
      render_tile<double>(ctx, x0, y0, out, counters.local());
    } else {
      render_tile<float>(ctx, x0, y0, out, counters.local());
    }
  });
  for (const auto& c : counters)
    for (int i = 0; i < kStageCount; ++i) {
      out.stages[kStageNames[i]].evals += c.stages[static_cast<size_t>(i)].evals;
      out.stages[kStageNames[i]].seconds += c.stages[static_cast<size_t>(i)].seconds;
    }
  for (const auto& [name, cost] : out.stages) out.total_evals += cost.evals;
  out.seconds = since(start);
  return out;
}

std::map<std::string, double> cost_metrics(const RenderResult& result) {
  std::map<std::string, double> m;
  for (const auto& [name, cost] : result.stages) {
    m["cost.stages." + name + ".evals"] = static_cast<double>(cost.evals);
    m["cost.stages." + name + ".seconds"] = cost.seconds;
  }
  m["cost.evals"] = static_cast<double>(result.total_evals);
  m["cost.evals_per_pixel"] = result.evals_per_pixel();
  m["cost.steps_max"] = result.steps.pixels.empty()
                            ? 0
                            : *std::max_element(result.steps.pixels.begin(), result.steps.pixels.end());
  m["cost.seconds"] = result.seconds;
  return m;
}

}  // namespace marchcheck::march
