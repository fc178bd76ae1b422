#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) into build-fuzz/ and runs each for FUZZ_SECONDS (default 25)
# starting from its committed corpus in tests/fuzz/corpus/. New inputs stay in build-fuzz/corpus/ (the repository's
# corpus only changes by hand); a crash, leak or hang fails the script and leaves the input in build-fuzz/findings/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
seconds=${FUZZ_SECONDS:-25}
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DMARCHCHECK_FUZZ=ON -DMARCHCHECK_BUILD_TESTS=OFF -DMARCHCHECK_BUILD_BENCH=OFF
targets=(fuzz_scene fuzz_mesh_obj fuzz_mesh_off fuzz_mesh_ply fuzz_mesh_stl)
# fuzz_scene meets GLSL nodes: their compiler is a module, loaded at run time, that no target links.
cmake --build build-fuzz --parallel "$(nproc)" --target "${targets[@]}" marchcheck_glslang
mkdir -p build-fuzz/findings
source scripts/sanitizer-options.sh
for target in "${targets[@]}"; do
  name=${target#fuzz_}
  mkdir -p "build-fuzz/corpus/$name"
  dict=()
  if [ -f "tests/fuzz/$name.dict" ]; then dict=("-dict=tests/fuzz/$name.dict"); fi
  log="build-fuzz/findings/$target.log"
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb: an input that makes a loader eat memory is a finding;
  # -seed: the same mutations on every CI run (longer runs by hand, without it, explore further).
  if ! "build-fuzz/tests/fuzz/$target" "build-fuzz/corpus/$name" "tests/fuzz/corpus/$name" "${dict[@]}" \
      -max_total_time="$seconds" -seed=1 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="build-fuzz/findings/$target-" >"$log" 2>&1; then
    tail -n 80 "$log"
    echo "fuzz: $target FAILED; the input is in build-fuzz/findings/"
    exit 1
  fi
  echo "fuzz: $target ok: $(grep -E '^stat::(number_of_executed_units|new_units_added)' "$log" | tr '\n' ' ')"
done
