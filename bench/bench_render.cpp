// Render time of lee-flat at its built-in size (1280x720) on all cores, and the two ratios of issue 7, each timed
// in one run with the renders alternating so machine load hits both sides alike:
//   P1 = straightforward port (lee_flat_port.cpp) / project renderer, on the same scene;
//   P2 = scene loaded from its JSON text / the same scene built in C++.
// Each ratio is of medians over the iterations. Real time, because the renderers are multi-threaded.
#include "lee_flat_port.hpp"

#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/scene_file.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace sdf = marchcheck::sdf;
namespace march = marchcheck::march;

namespace {

constexpr int kRuns = 7;  // per ratio: the medians of 7 runs of each side

sdf::Scene json_lee_flat() {
  return sdf::scene_from_json(sdf::scene_to_json(sdf::builtin_scene("lee-flat")), "lee-flat.json");
}

template <class F>
double seconds(F&& fn) {
  const auto start = std::chrono::steady_clock::now();
  fn();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// What `marchcheck render SCENE` computes: the colour image, no AOV.
march::RenderResult render_command(const sdf::Scene& scene) { return march::render(scene, {}, nullptr, march::Images::asked); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

void run_render(benchmark::State& state, const sdf::Scene& scene) {
  double evals_per_pixel = 0;
  for (auto _ : state) {
    const march::RenderResult result = render_command(scene);
    evals_per_pixel = result.evals_per_pixel();
    benchmark::DoNotOptimize(result.total_evals);
  }
  state.counters["evals_per_pixel"] = evals_per_pixel;  // deterministic: the last run's value is every run's
}

// Times `numerator` and `denominator` alternately and reports both medians and their ratio.
template <class A, class B>
void run_ratio(benchmark::State& state, const char* name, A&& numerator, B&& denominator) {
  std::vector<double> a, b;
  for (auto _ : state) {
    a.push_back(seconds(numerator));
    b.push_back(seconds(denominator));
  }
  state.counters["num_ms"] = median(a) * 1e3;
  state.counters["den_ms"] = median(b) * 1e3;
  state.counters[name] = median(a) / median(b);
  state.counters["spread"] = (*std::max_element(b.begin(), b.end()) - *std::min_element(b.begin(), b.end())) / median(b);
}

void BM_RenderLeeFlat(benchmark::State& state) { run_render(state, sdf::builtin_scene("lee-flat")); }

void BM_RenderLeeFlatJson(benchmark::State& state) { run_render(state, json_lee_flat()); }

void BM_RenderLeeFlatPort(benchmark::State& state) {
  const sdf::Scene scene = sdf::builtin_scene("lee-flat");
  for (auto _ : state) benchmark::DoNotOptimize(marchcheck::bench::render_lee_flat_port(scene).evals);
}

// P1: num = the port, den = the project.
void BM_P1_PortOverProject(benchmark::State& state) {
  const sdf::Scene scene = sdf::builtin_scene("lee-flat");
  run_ratio(
      state, "P1", [&] { benchmark::DoNotOptimize(marchcheck::bench::render_lee_flat_port(scene).evals); },
      [&] { benchmark::DoNotOptimize(render_command(scene).total_evals); });
}

// P2: num = the scene loaded from JSON, den = the scene built in C++.
void BM_P2_JsonOverCpp(benchmark::State& state) {
  const sdf::Scene cpp = sdf::builtin_scene("lee-flat"), json = json_lee_flat();
  run_ratio(
      state, "P2", [&] { benchmark::DoNotOptimize(render_command(json).total_evals); },
      [&] { benchmark::DoNotOptimize(render_command(cpp).total_evals); });
}

BENCHMARK(BM_RenderLeeFlat)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RenderLeeFlatJson)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RenderLeeFlatPort)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_P1_PortOverProject)->Iterations(kRuns)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_P2_JsonOverCpp)->Iterations(kRuns)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
