#!/usr/bin/env bash
# Regenerates reports/screenshot.png, the README's picture of the report, from reports/out/index.html
# (run scripts/main.sh first) with headless Chromium.
set -euo pipefail
cd "$(dirname "$0")/.."
test -f reports/out/index.html || { echo "screenshot: reports/out/index.html is missing; run scripts/main.sh" >&2; exit 2; }
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
chromium --headless --no-sandbox --disable-gpu --user-data-dir="$profile" --hide-scrollbars --window-size=1280,1600 \
  --virtual-time-budget=10000 --screenshot="$PWD/reports/screenshot.png" "file://$PWD/reports/out/index.html" 2>/dev/null
echo "screenshot: reports/screenshot.png"
