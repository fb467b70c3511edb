#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The one test command (README.md, .ci/run): installs what is missing, builds everything with
# warnings as errors, runs the whole test suite, then runs it again under ASan + UBSan.
#   scripts/test.sh            everything (default build + sanitizer build + a short fuzz pass)
#   scripts/test.sh --quick    default build only, slow tests skipped, no fuzzing
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1

scripts/install-deps.sh
jobs=$(nproc)

# The tests are built in Release (-O3 -DNDEBUG), the configuration a user builds first and the
# one the GPU report packs: GCC's -O3 flow analysis warns where -O2 does not, and -Werror must hold
# there. Debug is built by the sanitizer pass below.
echo "== build (Release) =="
cmake -S . -B build/test -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build/test -j"$jobs"
echo "== tests =="
if [ $quick -eq 1 ]; then
  (cd build/test && ctest -j"$jobs" --output-on-failure -LE slow)
  exit 0
fi
(cd build/test && ctest -j"$jobs" --output-on-failure)

echo "== build (ASan + UBSan) =="
# Benchmarks and the consumer projects add nothing under sanitizers; GL drivers allocate for the
# life of the process, so leak checking stays off (ASan's other checks stay on).
cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=Debug -DVPLKIT_SANITIZE=ON \
      -DVPLKIT_BUILD_BENCHMARKS=OFF
cmake --build build/sanitize -j"$jobs"
echo "== tests under ASan + UBSan =="
(cd build/sanitize && ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
   ctest -j"$jobs" --output-on-failure -LE 'slow|packaging')

echo "== fuzz (short pass: each libFuzzer harness 10 s, clang build in build/fuzz) =="
scripts/fuzz.sh 10
