#!/usr/bin/env bash
# Installs the build in BUILD into a temporary prefix, checks that the test helpers' headers pull in none of the
# libraries' private dependencies, then builds tests/consumer against that prefix and runs its tests.
# usage: tests/consumer/check.sh BUILD
set -euo pipefail
build=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cmake --install "$build" --prefix "$scratch/prefix" >/dev/null
# What a user's test includes reads GLM, GoogleTest and the standard library, nothing else.
private=$(c++ -std=c++20 -M -I"$scratch/prefix/include" -x c++ \
  - <<<'#include <marchcheck/validation/gtest_helpers.hpp>' | tr ' \\' '\n\n' | grep -E 'CGAL|OpenMesh|OpenImageIO|embree|tbb|nlohmann' || true)
if [ -n "$private" ]; then
  echo "consumer: gtest_helpers.hpp includes private dependencies:"; echo "$private"; exit 1
fi
cmake -S "$here" -B "$scratch/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$scratch/prefix" >/dev/null
cmake --build "$scratch/build"
ctest --test-dir "$scratch/build" --output-on-failure
