#!/usr/bin/env bash
# Installs every Debian 12 package marchcheck's build, tests and report need. Idempotent: skips what is installed.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config git
  libglm-dev libboost-dev libcgal-dev libopenmesh-dev libgtest-dev libgmock-dev libbenchmark-dev
  libopenimageio-dev openimageio-tools libtbb-dev libembree-dev  # OIIO's CMake package checks its tools exist
  libpng-dev  # the PNGs renders write, without loading OpenImageIO
  zlib1g-dev  # their rows deflated in pieces on every core
  libsleef-dev  # the march's float transcendentals, vectorised in the batched tape
  nlohmann-json3-dev libcli11-dev libfmt-dev
  glslang-dev glslang-tools spirv-tools spirv-headers  # GLSL fields; the glslang CMake package checks its tools
  libepoxy-dev libegl1 libopengl0 libgl1-mesa-dri libegl-mesa0  # the GL driver: EGL surfaceless, Mesa llvmpipe, through
  # libepoxy, which loads libEGL and libOpenGL on first use
  python3 python3-matplotlib chromium  # plots and the report's browser test
  clang libclang-rt-dev  # scripts/fuzz.sh: libFuzzer and clang's sanitizer runtimes
  strace  # .ci/run: ../shared/tools/fresh-deps replays the configure step under it
  libopenmpi-dev openmpi-bin  # sweep and validate under mpirun (optional: the build works without them)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "setup: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
