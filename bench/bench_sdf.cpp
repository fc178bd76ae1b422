// SDF evaluations per second: lee-flat written by hand in C++, as a compiled tape, and as a tape compiled from
// the scene's JSON text; then every built-in scene's tape, one point at a time (Tape) and in batches (Batch), on
// one thread and on all (tasks of 256 points under oneTBB, as the renderer's tiles), and its camera's rays
// marched one at a time (MarchRays) and as packets (MarchPackets); or, given scene files (bench_sdf --scene
// my.json), theirs. Compare "evals/s" of
// BM_LeeFlatCpp and BM_LeeFlatTape to read what the tape interpreter costs over hand-written code, and
// BM_LeeFlatGlsl (hand-written GLSL) and BM_LeeFlatExportedGlsl (the built-in exported and imported back) beside
// BM_LeeFlatTape for what a field imported from GLSL costs.
#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/packet.hpp"
#include "marchcheck/march/render.hpp"
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
#include <deque>
#include <iostream>
#include <memory>
#include <random>
#include <string_view>
#include <vector>

namespace sdf = marchcheck::sdf;

namespace {

constexpr int kPoints = 1 << 14, kTask = 256;

// The lee-flat field: sphere centre (0, 1.2, 0) radius 1, united with the ground plane y = 0.
float lee_flat_sdf(glm::vec3 p) { return glm::min(glm::length(p - glm::vec3(0, 1.2f, 0)) - 1.0f, p.y); }

// Points generated once with a fixed seed over a box, so only evaluation is timed.
struct Points {
  std::vector<glm::vec3> p;
  std::vector<float> x, y, z;  // the same, as structure of arrays
};
Points points_in(glm::dvec3 lo, glm::dvec3 hi) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0, 1);
  Points v;
  for (int i = 0; i < kPoints; ++i) {
    v.p.push_back(glm::vec3(lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng))));
    v.x.push_back(v.p.back().x);
    v.y.push_back(v.p.back().y);
    v.z.push_back(v.p.back().z);
  }
  return v;
}
// The box the built-in scenes live in.
const Points& points() {
  static const Points pts = points_in({-4, -1, -4}, {4, 3, 4});
  return pts;
}

template <class F>
void run_evals(benchmark::State& state, F&& field) {
  const Points& pts = points();
  for (auto _ : state)
    for (const glm::vec3& p : pts.p) benchmark::DoNotOptimize(field(p));
  state.counters["evals/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * pts.p.size()), benchmark::Counter::kIsRate);
}

// Runs eval_range(begin, end, out) over all of pts in tasks of kTask on state.range(0) threads.
template <class F>
void run_threaded(benchmark::State& state, const Points& pts, F&& eval_range) {
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

// A scene's tape, one point at a time (BM_SceneTape/NAME) and in batches (BM_SceneBatch/NAME), on one thread and
// on all, at pts. Real time: the threads share one clock.
void register_scene(const sdf::Scene& scene, const Points& points_of_scene) {
  const Points* pts = &points_of_scene;  // outlives the run: the built-ins' or main's
  const auto tape = std::make_shared<const sdf::Tape>(sdf::compile(scene));  // its time and precision
  const int all = tbb::info::default_concurrency();
  benchmark::RegisterBenchmark(("BM_SceneTape/" + scene.name).c_str(), [tape, pts](benchmark::State& state) {
    run_threaded(state, *pts, [&](int begin, int end, float* out) {
      for (int i = begin; i < end; ++i) out[i] = sdf::evaluate<float>(*tape, pts->p[static_cast<size_t>(i)]);
    });
  })->Arg(1)->Arg(all)->ArgName("threads")->UseRealTime();
  benchmark::RegisterBenchmark(("BM_SceneBatch/" + scene.name).c_str(), [tape, pts](benchmark::State& state) {
    run_threaded(state, *pts, [&](int begin, int end, float* out) {
      for (int i = begin; i < end; i += sdf::kBatch) {
        const auto at = static_cast<size_t>(i);
        sdf::evaluate_batch(*tape, &pts->x[at], &pts->y[at], &pts->z[at], out + i, std::min(sdf::kBatch, end - i));
      }
    });
  })->Arg(1)->Arg(all)->ArgName("threads")->UseRealTime();
}

// The scene's camera rays at 160x90 marched on one thread with its own settings, one ray at a time through the
// one-point tape (BM_SceneMarchRays/NAME) and as packets through the batched tape (BM_SceneMarchPackets/NAME):
// the same steps (tests/march/test_packet.cpp), so their evals/s compare the two paths on coherent points, where
// neighbouring lanes' queries share work (a mesh's search starts from the neighbour's leaf).
void register_march(const sdf::Scene& scene) {
  using marchcheck::march::PacketRay;
  using marchcheck::march::RayRecord;
  const auto tape = std::make_shared<const sdf::Tape>(sdf::compile(scene));
  const marchcheck::march::Camera camera(scene.camera, 160, 90);
  const marchcheck::march::MarchContext context = marchcheck::march::march_context(camera, scene);
  auto rays = std::make_shared<std::vector<PacketRay<float>>>();
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 160; ++x) {
      const marchcheck::march::Ray ray = camera.ray(x + 0.5, y + 0.5);
      rays->push_back({glm::vec3(ray.origin), glm::vec3(ray.direction), scene.march.max_dist});
    }
  const auto evals_per_second = [](benchmark::State& state, const std::vector<RayRecord<float>>& records) {
    double evals = 0;
    for (const auto& r : records) evals += r.evals;
    state.counters["evals/s"] = benchmark::Counter(evals * static_cast<double>(state.iterations()),
                                                   benchmark::Counter::kIsRate);
  };
  const sdf::MarchSettings settings = scene.march;
  benchmark::RegisterBenchmark(("BM_SceneMarchRays/" + scene.name).c_str(), [=](benchmark::State& state) {
    std::vector<RayRecord<float>> records(rays->size());
    const marchcheck::march::TapeField field{tape.get()};
    for (auto _ : state)
      for (size_t i = 0; i < rays->size(); ++i)
        records[i] = marchcheck::march::march<float>(field, (*rays)[i].origin, (*rays)[i].direction, settings, context);
    evals_per_second(state, records);
  });
  const auto packets = [=](const std::string& name, const sdf::MarchSettings& s) {
    benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
      std::vector<RayRecord<float>> records(rays->size());
      for (auto _ : state)
        marchcheck::march::march_packet(*tape, rays->data(), records.data(), static_cast<int>(rays->size()), s,
                                        context);
      evals_per_second(state, records);
    });
  };
  packets("BM_SceneMarchPackets/" + scene.name, settings);
  // Each marcher on the same rays (BM_SceneMarcher/NAME/MARCHER): seconds should follow evaluations, so their
  // evals/s should agree (within 1.2x, issue 16) whatever the marcher's bookkeeping.
  for (const char* marcher : {"sphere", "relaxed", "scaled", "fixed", "sphere+secant", "relaxed+secant"}) {
    sdf::Scene variant = scene;
    const std::string_view name(marcher);
    const size_t plus = name.find('+');
    sdf::apply_setting(variant, "marcher", std::string(name.substr(0, plus)));
    sdf::apply_setting(variant, "refine", plus == std::string_view::npos ? "none" : "secant");
    packets("BM_SceneMarcher/" + scene.name + "/" + marcher, variant.march);
  }
}

// A scene file's points: 1.2 times the box its field's zero set lies in (a mesh's: its bounding box), or the
// built-ins' box where that is unbounded (a plane, a repetition).
Points points_for(const sdf::Scene& scene) {
  const sdf::Box3 box = sdf::derive_info(scene.root, scene.time).bounds;
  if (!box.is_finite()) return points();
  return points_in(box.center() - 0.6 * box.size(), box.center() + 0.6 * box.size());
}

}  // namespace

// bench_sdf [--scene FILE]... [Google Benchmark's flags]: with scene files, their tapes (a user's own field or
// mesh) instead of every built-in's; the fixed lee-flat comparisons run either way.
int main(int argc, char** argv) {
  std::vector<std::string> files;
  std::vector<char*> args{argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (std::string_view(argv[i]) == "--scene" && i + 1 < argc) {
      files.push_back(argv[++i]);
    } else {
      args.push_back(argv[i]);
    }
  }
  std::deque<Points> file_points;
  try {
    for (const std::string& file : files) {
      const sdf::Scene scene = sdf::load_scene_file(file);
      register_scene(scene, file_points.emplace_back(points_for(scene)));
      register_march(scene);
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_sdf: " << e.what() << "\n";
    return 2;
  }
  if (files.empty())
    for (const std::string& name : sdf::builtin_scene_names()) {
      const sdf::Scene scene = sdf::builtin_scene(name);
      register_scene(scene, points());
      register_march(scene);
    }
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
