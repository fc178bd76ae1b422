// SDF evaluations per second: lee-flat written by hand in C++, as a compiled tape, and as a tape compiled from
// the scene's JSON text; then every built-in scene's tape. Compare "evals/s" of BM_LeeFlatCpp and
// BM_LeeFlatTape to read what the tape interpreter costs over hand-written code.
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/sdf/tape.hpp"
#include "marchcheck/validation/mesh_loader.hpp"

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>

#include <random>
#include <vector>

namespace sdf = marchcheck::sdf;

namespace {

// The lee-flat field: sphere centre (0, 1.2, 0) radius 1, united with the ground plane y = 0.
float lee_flat_sdf(glm::vec3 p) { return glm::min(glm::length(p - glm::vec3(0, 1.2f, 0)) - 1.0f, p.y); }

// Points generated once with a fixed seed over the box the scenes live in, so only evaluation is timed.
const std::vector<glm::vec3>& points() {
  static const std::vector<glm::vec3> pts = [] {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> x(-4, 4), y(-1, 3);
    std::vector<glm::vec3> v(4096);
    for (auto& p : v) p = {x(rng), y(rng), x(rng)};
    return v;
  }();
  return pts;
}

template <class F>
void run_evals(benchmark::State& state, F&& field) {
  const auto& pts = points();
  for (auto _ : state)
    for (const glm::vec3& p : pts) benchmark::DoNotOptimize(field(p));
  state.counters["evals/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * pts.size()), benchmark::Counter::kIsRate);
}

void BM_LeeFlatCpp(benchmark::State& state) { run_evals(state, lee_flat_sdf); }

void BM_LeeFlatTape(benchmark::State& state) {
  const sdf::Tape tape = sdf::compile(sdf::builtin_scene("lee-flat").root);
  run_evals(state, [&](glm::vec3 p) { return sdf::evaluate<float>(tape, p); });
}

// Through the scene file text, to show a loaded scene evaluates as fast as a built-in one.
void BM_LeeFlatJsonTape(benchmark::State& state) {
  const sdf::Scene scene = sdf::scene_from_json(sdf::scene_to_json(sdf::builtin_scene("lee-flat")), "lee-flat.json");
  const sdf::Tape tape = sdf::compile(scene.root, scene.time);
  run_evals(state, [&](glm::vec3 p) { return sdf::evaluate<float>(tape, p); });
}

BENCHMARK(BM_LeeFlatCpp);
BENCHMARK(BM_LeeFlatTape);
BENCHMARK(BM_LeeFlatJsonTape);

// One benchmark per built-in scene, registered at start-up so a new scene is measured without editing this file.
const bool registered = [] {
  for (const std::string& name : sdf::builtin_scene_names()) {
    benchmark::RegisterBenchmark(("BM_SceneTape/" + name).c_str(), [name](benchmark::State& state) {
      const sdf::Scene scene = sdf::builtin_scene(name, marchcheck::validation::mesh_loader());
      const sdf::Tape tape = sdf::compile(scene.root, scene.time);  // time: animated scenes
      run_evals(state, [&](glm::vec3 p) { return sdf::evaluate<float>(tape, p); });
    });
  }
  return true;
}();

}  // namespace
