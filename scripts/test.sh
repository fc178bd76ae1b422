#!/usr/bin/env bash
# Installs the dependencies, builds, and runs every test (fast and slow).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)"
