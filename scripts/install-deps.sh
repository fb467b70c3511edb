#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian 12 packages vplkit's build, tests, examples and benchmarks need, skipping
# those already present. Safe to run again. Needs root (or sudo) only when something is missing.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  libglm-dev                       # the vector vocabulary (mirrors GLSL)
  catch2                           # Catch2 v2 single header, unit/statistical tests
  libbenchmark-dev                 # Google Benchmark, tests/bench
  glslang-tools                    # glslangValidator: GLSL compile checks (GL 4.30 and Vulkan SPIR-V)
  libepoxy-dev                     # GL function loader
  libegl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6-dev   # headless GL: EGL surfaceless + OSMesa (llvmpipe)
  libglfw3-dev xvfb xauth          # --window and its smoke test
  libopenexr-dev                   # linear HDR output
  libstb-dev                       # PNG preview writer, texture loading
  libtinyobjloader-dev             # OBJ/MTL scenes
  nlohmann-json3-dev               # JSON run reports
  libcli11-dev                     # command-line parsing of the example renderer
  clang libclang-rt-14-dev         # libFuzzer harnesses (tests/fuzz, scripts/fuzz.sh)
  libembree-dev                    # Embree 3: the reference of the BVH (exact visibility) tests and benchmark
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers  # Vulkan tests: loader, lavapipe, validation layer
  spirv-cross                      # SPIR-V reflection: the kernels' default bindings as Vulkan sees them
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
