// SDF evaluations per second: lee-flat written by hand in C++, as a compiled tape, and as a tape compiled from
// the scene's JSON text; then every built-in scene's tape, one point at a time (Tape) and in batches (Batch), on
// one thread and on all (tasks of 256 points under oneTBB, as the renderer's tiles). Compare "evals/s" of
// BM_LeeFlatCpp and BM_LeeFlatTape to read what the tape interpreter costs over hand-written code, and
// BM_LeeFlatGlsl (hand-written GLSL) and BM_LeeFlatExportedGlsl (the built-in exported and imported back) beside
// BM_LeeFlatTape for what a field imported from GLSL costs.
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/glsl_export.hpp"
#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <random>
#include <vector>

namespace sdf = marchcheck::sdf;

namespace {

constexpr int kPoints = 1 << 14, kTask = 256;

// The lee-flat field: sphere centre (0, 1.2, 0) radius 1, united with the ground plane y = 0.
float lee_flat_sdf(glm::vec3 p) { return glm::min(glm::length(p - glm::vec3(0, 1.2f, 0)) - 1.0f, p.y); }

// Points generated once with a fixed seed over the box the scenes live in, so only evaluation is timed.
struct Points {
  std::vector<glm::vec3> p;
  std::vector<float> x, y, z;  // the same, as structure of arrays
};
const Points& points() {
  static const Points pts = [] {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> x(-4, 4), y(-1, 3);
    Points v;
    for (int i = 0; i < kPoints; ++i) {
      v.p.push_back({x(rng), y(rng), x(rng)});
      v.x.push_back(v.p.back().x);
      v.y.push_back(v.p.back().y);
      v.z.push_back(v.p.back().z);
    }
    return v;
  }();
  return pts;
}

template <class F>
void run_evals(benchmark::State& state, F&& field) {
  const auto& pts = points();
  for (auto _ : state)
    for (const glm::vec3& p : pts.p) benchmark::DoNotOptimize(field(p));
  state.counters["evals/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * pts.p.size()), benchmark::Counter::kIsRate);
}

// Runs eval_range(begin, end, out) over all points in tasks of kTask on state.range(0) threads.
template <class F>
void run_threaded(benchmark::State& state, F&& eval_range) {
  const auto& pts = points();
  std::vector<float> out(pts.p.size());
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    arena.execute([&] {
      tbb::parallel_for(0, kPoints / kTask, [&](int task) { eval_range(task * kTask, (task + 1) * kTask, out.data()); });
    });
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["evals/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * pts.p.size()), benchmark::Counter::kIsRate);
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

// The same field written in GLSL as Shadertoy code writes it and evaluated by the SPIR-V evaluator: the
// imported field's cost beside the tape's (BM_LeeFlatTape) on the same points.
void BM_LeeFlatGlsl(benchmark::State& state) {
  sdf::Node n = sdf::make(sdf::Op::glsl);
  sdf::GlslSpec spec;
  spec.code = "float map(vec3 p) { return min(length(p - vec3(0.0, 1.2, 0.0)) - 1.0, p.y); }";
  spec.kind = sdf::Kind::bound;
  spec.measured = false;
  n.glsl = std::make_shared<const sdf::GlslField>(spec, spec.code, "lee_flat.glsl");
  const sdf::Tape tape = sdf::compile(n);
  run_evals(state, [&](glm::vec3 p) { return sdf::evaluate<float>(tape, p); });
}

// The built-in lee-flat exported as GLSL (sdf::glsl_map: the tape one statement per instruction) and imported
// back: the round trip, beside BM_LeeFlatTape on the same points.
void BM_LeeFlatExportedGlsl(benchmark::State& state) {
  const sdf::Scene scene = sdf::builtin_scene("lee-flat");
  sdf::Node n = sdf::make(sdf::Op::glsl);
  sdf::GlslSpec spec;
  spec.code = sdf::glsl_map(scene.root, scene.time, scene.name);
  spec.kind = sdf::Kind::bound;
  spec.measured = false;
  n.glsl = std::make_shared<const sdf::GlslField>(spec, spec.code, "lee-flat.glsl");
  const sdf::Tape tape = sdf::compile(n);
  run_evals(state, [&](glm::vec3 p) { return sdf::evaluate<float>(tape, p); });
}

BENCHMARK(BM_LeeFlatCpp);
BENCHMARK(BM_LeeFlatTape);
BENCHMARK(BM_LeeFlatJsonTape);
BENCHMARK(BM_LeeFlatGlsl);
BENCHMARK(BM_LeeFlatExportedGlsl);

sdf::Tape scene_tape(const std::string& name) {
  const sdf::Scene scene = sdf::builtin_scene(name);
  return sdf::compile(scene.root, scene.time);  // time: animated scenes
}

// One benchmark per built-in scene and thread count, registered at start-up so a new scene is measured without
// editing this file. Real time: the threads share one clock.
const bool registered = [] {
  const int all = tbb::info::default_concurrency();
  for (const std::string& name : sdf::builtin_scene_names()) {
    benchmark::RegisterBenchmark(("BM_SceneTape/" + name).c_str(), [name](benchmark::State& state) {
      const sdf::Tape tape = scene_tape(name);
      const auto& pts = points();
      run_threaded(state, [&](int begin, int end, float* out) {
        for (int i = begin; i < end; ++i) out[i] = sdf::evaluate<float>(tape, pts.p[static_cast<size_t>(i)]);
      });
    })->Arg(1)->Arg(all)->ArgName("threads")->UseRealTime();
    benchmark::RegisterBenchmark(("BM_SceneBatch/" + name).c_str(), [name](benchmark::State& state) {
      const sdf::Tape tape = scene_tape(name);
      const auto& pts = points();
      run_threaded(state, [&](int begin, int end, float* out) {
        for (int i = begin; i < end; i += sdf::kBatch) {
          const auto at = static_cast<size_t>(i);
          sdf::evaluate_batch(tape, &pts.x[at], &pts.y[at], &pts.z[at], out + i, std::min(sdf::kBatch, end - i));
        }
      });
    })->Arg(1)->Arg(all)->ArgName("threads")->UseRealTime();
  }
  return true;
}();

}  // namespace
