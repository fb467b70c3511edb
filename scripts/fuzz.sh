#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the libFuzzer harnesses (tests/fuzz, docs/fuzzing.md) in their own clang build folder,
# build/fuzz, and runs each one from its seed corpus through ctest (label fuzz).
#   scripts/fuzz.sh                    the short pass of scripts/test.sh: 10 s per harness
#   scripts/fuzz.sh 600                every harness for 600 s
#   scripts/fuzz.sh 600 obj_loader     one harness (distribution, include_resolver, obj_loader)
# A crash input lands in build/fuzz/tests/fuzz/artifacts/; replay it with
#   build/fuzz/tests/fuzz/fuzz_<name> <file>
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
only=${2:-}
cmake -S . -B build/fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DVPLKIT_BUILD_FUZZERS=ON -DVPLKIT_BUILD_TESTS=OFF -DVPLKIT_BUILD_EXAMPLES=OFF \
      -DVPLKIT_BUILD_BENCHMARKS=OFF -DVPLKIT_GL_TESTS=OFF -DVPLKIT_INSTALL=OFF \
      -DVPLKIT_FUZZ_SECONDS="$seconds" > /dev/null
cmake --build build/fuzz -j"$(nproc)"
cd build/fuzz
if [ -n "$only" ]; then
  ctest --output-on-failure -L fuzz -R "^fuzz_${only}\$"
else
  ctest --output-on-failure -L fuzz
fi
