#!/usr/bin/env bash
# Builds a portable Debian package (no -march=native, no tests or benchmarks) into build-deb/, installs it with
# apt (which installs what it depends on), checks that the installed program runs and that tests/consumer builds
# against /usr and passes, then removes it again unless --keep is given.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake -S . -B build-deb -G Ninja -DCMAKE_BUILD_TYPE=Release -DMARCHCHECK_NATIVE=OFF -DMARCHCHECK_BUILD_TESTS=OFF \
  -DMARCHCHECK_BUILD_BENCH=OFF
cmake --build build-deb --parallel "$(nproc)"
(cd build-deb && cpack -G DEB)
deb=$(ls build-deb/marchcheck_*.deb)
echo "package: $deb"; dpkg-deb --field "$deb" Depends Recommends
sudo=""; if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "./$deb" >/dev/null
if [ "${1:-}" != "--keep" ]; then trap '$sudo apt-get purge -y -qq marchcheck >/dev/null' EXIT; fi
marchcheck scenes >/dev/null
scratch=$(mktemp -d)
# A texture and an EXR: the installed program finds its OpenImageIO module (libmarchcheck_oiio.so) beside its libraries.
marchcheck render lee-textured --size 32x18 -o "$scratch/textured.exr" >/dev/null
# A mesh file: its OpenMesh module (libmarchcheck_openmesh.so) too.
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$scratch/tetra.off"
echo '{"sdf": {"mesh": "tetra.off"}}' >"$scratch/tetra.json"
marchcheck render "$scratch/tetra.json" --size 32x18 -o "$scratch/tetra.png" >/dev/null
cmake -S tests/consumer -B "$scratch" -G Ninja >/dev/null
cmake --build "$scratch" >/dev/null
ctest --test-dir "$scratch" --output-on-failure
rm -rf "$scratch"
