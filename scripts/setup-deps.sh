#!/usr/bin/env bash
# Installs every Debian package caustix needs to build, run and test.
# Idempotent; safe to run on a fresh Debian 12 machine (as root, or with sudo).
set -euo pipefail

PACKAGES=(
  # build
  build-essential cmake pkg-config ninja-build
  # libraries of the design card
  libopenmesh-dev libcgal-dev libeigen3-dev libdraco-dev
  libopenimageio-dev openimageio-tools libglfw3-dev libglm-dev
  # OpenGL: loader, EGL/GL headers and Mesa's software driver (listed
  # explicitly: the EGL package does not pull in the DRI driver)
  libepoxy-dev libegl-dev libgl-dev libgles-dev libgl1-mesa-dri libegl-mesa0
  # windowed tests without a display
  xvfb xauth
  # small well-kept libraries: JSON, CLI parsing, checksums, threading
  nlohmann-json3-dev libcli11-dev libxxhash-dev libzstd-dev libtbb-dev
  # glTF 2.0 input (bake/src/gltf_import.cpp)
  libtinygltf-dev
  # Dear ImGui: caustix-view's panel (the GLFW and OpenGL 3 back ends are compiled from its sources)
  libimgui-dev
  # Embree: the light-transport tables' rays (bake/src/ray_cast_embree.cpp)
  libembree-dev
  # tests: GoogleTest, libFuzzer (clang-14 + its runtime), Python for plots
  libgtest-dev clang-14 libclang-rt-14-dev python3
  # scripts/plot_runtime.py and the other plots of docs/results/; zstd's
  # command for scripts/bench-ltt-zstd.sh
  python3-matplotlib zstd
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "setup-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup-deps: done"
