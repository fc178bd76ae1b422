// Render time of lee-flat at its built-in size (1280x720), built in C++ and loaded from its JSON text: the two
// times should match, since both compile to the same tape. Real time, because the renderer is multi-threaded.
#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/scene_file.hpp"

#include <benchmark/benchmark.h>

namespace sdf = marchcheck::sdf;
namespace march = marchcheck::march;

namespace {

void run_render(benchmark::State& state, const sdf::Scene& scene) {
  double evals_per_pixel = 0;
  for (auto _ : state) {
    const march::RenderResult result = march::render(scene);
    evals_per_pixel = result.evals_per_pixel();
    benchmark::DoNotOptimize(result.total_evals);
  }
  state.counters["evals_per_pixel"] = evals_per_pixel;  // deterministic: the last run's value is every run's
}

void BM_RenderLeeFlat(benchmark::State& state) { run_render(state, sdf::builtin_scene("lee-flat")); }

void BM_RenderLeeFlatJson(benchmark::State& state) {
  run_render(state, sdf::scene_from_json(sdf::scene_to_json(sdf::builtin_scene("lee-flat")), "lee-flat.json"));
}

BENCHMARK(BM_RenderLeeFlat)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RenderLeeFlatJson)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
