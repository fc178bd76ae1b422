#!/usr/bin/env bash
# Installs the dependencies, builds, and writes the accuracy report of the built-in scenes and a GLSL example to
# reports/out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
status=0
# Every built-in scene, and a GLSL map as a Shadertoy user writes it (examples/), judged like the others.
build/cli/marchcheck report -o reports/out all examples/shadertoy_map.glsl || status=$?
# 1 means the report is written and a check failed: its summary says which. Only 2 (bad input, nothing written)
# is a failure of this job.
if ((status == 2)); then exit 2; fi
echo "Open reports/out/index.html in a browser (exit status of marchcheck report: $status)"
