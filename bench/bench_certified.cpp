// What certainty costs: per built-in scene the certified reference judges (no closed form), first hits per
// second along the camera's rays by interval arithmetic (BM_CertifiedHit) beside the numerical root finder that
// trusts the declared Lipschitz constant (BM_NumericalHit) on the same rays, and interval evaluations of the tape
// per second over boxes 1e-3 wide (BM_IntervalEval) beside double ones (BM_DoubleEval). One thread each.
#include "marchcheck/march/camera.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/interval.hpp"
#include "marchcheck/validation/certified.hpp"
#include "marchcheck/validation/reference.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace marchcheck;

struct Rays {
  std::vector<glm::dvec3> origin, direction;
  double t_max;
};

// A 16 x 9 grid of the scene's camera rays.
Rays camera_rays(const sdf::Scene& s) {
  const march::Camera camera(s.camera, s.width, s.height);
  Rays r{{}, {}, std::isfinite(s.march.max_dist) ? s.march.max_dist : 1e6};
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 16; ++x) {
      const march::Ray ray = camera.ray((x + 0.5) * s.width / 16, (y + 0.5) * s.height / 9);
      r.origin.push_back(ray.origin);
      r.direction.push_back(glm::normalize(ray.direction));
    }
  return r;
}

template <class Cast>
void run_rays(benchmark::State& state, const Rays& rays, Cast cast) {
  for (auto _ : state)
    for (size_t i = 0; i < rays.origin.size(); ++i) benchmark::DoNotOptimize(cast(rays.origin[i], rays.direction[i]));
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(state.iterations() * rays.origin.size()),
                                                benchmark::Counter::kIsRate);
}

std::vector<glm::dvec3> box_centres() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<glm::dvec3> out(1024);
  for (auto& c : out) c = {u(rng), u(rng) + 1, u(rng)};
  return out;
}

const bool registered = [] {
  for (const std::string& name : sdf::builtin_scene_names()) {
    const sdf::Scene scene = sdf::builtin_scene(name);
    if (!scene.defects.empty()) continue;  // the same fields as their correct scenes
    if (validation::Reference(scene.root, scene.time).kind() != validation::ReferenceKind::certified) continue;
    benchmark::RegisterBenchmark(("BM_CertifiedHit/" + name).c_str(), [scene](benchmark::State& state) {
      const sdf::Tape tape = sdf::compile(scene.root, scene.time);
      const Rays rays = camera_rays(scene);
      run_rays(state, rays, [&](glm::dvec3 o, glm::dvec3 d) {
        return validation::certified_first_hit(tape, o, d, rays.t_max).t;
      });
    });
    benchmark::RegisterBenchmark(("BM_NumericalHit/" + name).c_str(), [scene](benchmark::State& state) {
      const validation::Reference ref(scene.root, scene.time);
      const Rays rays = camera_rays(scene);
      run_rays(state, rays, [&](glm::dvec3 o, glm::dvec3 d) { return ref.numerical_first_hit(o, d, rays.t_max).t; });
    });
    benchmark::RegisterBenchmark(("BM_IntervalEval/" + name).c_str(), [scene](benchmark::State& state) {
      const sdf::Tape tape = sdf::compile(scene.root, scene.time);
      const std::vector<glm::dvec3> centres = box_centres();
      for (auto _ : state)
        for (const glm::dvec3 c : centres)
          benchmark::DoNotOptimize(sdf::evaluate(tape, glm::vec<3, sdf::Interval>(
                                                           sdf::Interval(c.x, c.x + 1e-3), sdf::Interval(c.y, c.y + 1e-3),
                                                           sdf::Interval(c.z, c.z + 1e-3))));
      state.counters["evals/s"] = benchmark::Counter(static_cast<double>(state.iterations() * centres.size()),
                                                     benchmark::Counter::kIsRate);
    });
    benchmark::RegisterBenchmark(("BM_DoubleEval/" + name).c_str(), [scene](benchmark::State& state) {
      const sdf::Tape tape = sdf::compile(scene.root, scene.time);
      const std::vector<glm::dvec3> centres = box_centres();
      for (auto _ : state)
        for (const glm::dvec3 c : centres) benchmark::DoNotOptimize(sdf::evaluate(tape, c));
      state.counters["evals/s"] = benchmark::Counter(static_cast<double>(state.iterations() * centres.size()),
                                                     benchmark::Counter::kIsRate);
    });
  }
  return true;
}();

}  // namespace
