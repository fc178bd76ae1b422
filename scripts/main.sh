#!/usr/bin/env bash
# Installs the dependencies, builds, and runs the main job into reports/out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
build/cli/marchcheck render-all -o reports/out
echo "Images and per-scene cost: reports/out/"
