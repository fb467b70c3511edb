#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The first command a new user runs: installs what is missing, builds the example renderer and
# renders the built-in Cornell scene with the gathering-based CDF (gbg) on headless OpenGL
# (EGL surfaceless on Mesa llvmpipe when there is no GPU).
#   scripts/render-default.sh [extra vplrender flags]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DVPLKIT_BUILD_TESTS=OFF \
      -DVPLKIT_BUILD_BENCHMARKS=OFF
cmake --build build/release --target vplrender -j"$(nproc)"
mkdir -p out
build/release/examples/vplrender/vplrender --scene cornell --method gbg --out out/cornell_gbg.exr "$@"
