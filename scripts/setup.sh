#!/usr/bin/env bash
# Installs the Debian 12 packages Penumbra needs (only those missing), then
# configures and builds a Release tree in build/. Idempotent; quiet when all
# is already there. Usage: scripts/setup.sh [--no-build] [--farm]
#   --farm  also installs Slurm and munge (a one-node Slurm for scripts/farm, docs/farm.md)
#           and python3-yaml (the Kubernetes manifest's test)
set -euo pipefail
cd "$(dirname "$0")/.."

build=1
farm=0
for arg in "$@"; do
  case "$arg" in
    --no-build) build=0 ;;
    --farm) farm=1 ;;
    *) echo "setup: unknown argument '$arg' (--no-build, --farm)" >&2; exit 2 ;;
  esac
done

packages=(
  build-essential cmake pkg-config ninja-build
  libembree-dev libtbb-dev libglm-dev
  nlohmann-json3-dev libcli11-dev libtinyobjloader-dev libtinygltf-dev libopenexr-dev libstb-dev
  libdraco-dev libmeshoptimizer-dev libwebp-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libglfw3-dev libimgui-dev python3-glad
  libegl-dev libegl1-mesa-dev libgl-dev libgl1-mesa-dri libosmesa6-dev
  xvfb xauth
  python3 python3-matplotlib
  clang libclang-rt-14-dev
)
[ "$farm" -eq 1 ] && packages+=(slurm-wlm munge python3-yaml)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

[ "$build" -eq 1 ] || exit 0

jobs=$(nproc 2>/dev/null || echo 2)
log=$(mktemp)
trap 'rm -f "$log"' EXIT
if [ ! -f build/CMakeCache.txt ]; then
  # A unity build, like the sanitizer trees (scripts/sanitized_build.sh): half the build time
  # on 2 cores, the same images byte for byte. -DCMAKE_UNITY_BUILD=OFF builds file by file.
  source scripts/sanitized_build.sh  # PENUMBRA_UNITY_FLAGS
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${PENUMBRA_UNITY_FLAGS[@]}" >"$log" 2>&1 || { cat "$log"; exit 1; }
fi
# Quiet on success; the whole compiler output on failure.
if ! cmake --build build -j "$jobs" >"$log" 2>&1; then
  cat "$log"
  exit 1
fi
