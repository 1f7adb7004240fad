#!/usr/bin/env bash
# One-step set-up: install the Debian packages epi needs (only if missing), configure a
# Release build with Ninja into build/, and build everything. Idempotent; safe to re-run.
#   EPI_BUILD_DIR   build folder (default: build)
#   EPI_BUILD_TYPE  CMake build type (default: Release)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${EPI_BUILD_DIR:-$root/build}
build_type=${EPI_BUILD_TYPE:-Release}

packages=(
  cmake ninja-build g++ pkg-config ccache xauth
  libembree-dev libtbb-dev libglfw3-dev libglm-dev libopenimageio-dev libosd-dev
  libtinygltf-dev nlohmann-json3-dev libhwy-dev libgtest-dev libbenchmark-dev libimgui-dev
  libcli11-dev xvfb libgl-dev libgl1-mesa-dri mesa-utils libcairo2-dev libgif-dev libpng-dev xdotool
  clang libclang-rt-14-dev  # the sanitizer and fuzz builds of tools/test.sh
  python3-matplotlib  # bench/ plots (run with /usr/bin/python3: Debian's, not a pyenv one)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [ ! -f "$build_dir/build.ninja" ]; then
  cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" "${launcher[@]}" >/dev/null
fi
cmake --build "$build_dir" -j "$(nproc)"
