#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ (GCC, -O1) and runs
# every test (fast and slow). The first report aborts the test that made it, so ctest fails.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# Without MPI: the default build uses Open MPI where it is installed (as setup.sh installs it), so this is the build
# that shows marchcheck still builds and passes without it.
# -O1: sanitized code compiles faster than at -O3 and still inlines enough to keep the tests quick.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g1 -DNDEBUG" \
  -DMARCHCHECK_SANITIZE=ON -DMARCHCHECK_BUILD_BENCH=OFF -DMARCHCHECK_MPI=OFF "$@"
cmake --build build-asan --parallel "$(nproc)"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:check_initialization_order=1:strict_init_order=1"
source scripts/sanitizer-options.sh
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
ctest --test-dir build-asan --output-on-failure --parallel "$(nproc)" --timeout 600
