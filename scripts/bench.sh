#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the Google Benchmark suite (tests/bench/bench_<area>.cpp) in Release and runs every
# program with repetitions, writing per program JSON (what the table is made from), the console
# table (.txt) and a log (.log: context, GL renderer), plus results.md: one markdown table with
# the median and the min of the repetitions per benchmark (scripts/bench_to_markdown.awk; no
# Python, no jq) and machine.txt (date, commit, compiler, load, lscpu, GL renderer).
#
#   scripts/bench.sh                      build into build/bench, results into build/bench/results
#   scripts/bench.sh OUT_DIR              results into OUT_DIR (relative to the repository root)
#   scripts/bench.sh OUT_DIR ARGS...      extra Google Benchmark flags for every program,
#                                         e.g. --benchmark_filter=gbg
# Environment:
#   VPLKIT_BENCH_BUILD_DIR  build directory (default build/bench)
#   VPLKIT_BENCH_REPS       repetitions (default 3)
#   VPLKIT_BENCH_MIN_TIME   seconds per repetition of a benchmark (default 0.05)
#   VPLKIT_BENCH_GL         ON (default) builds bench_gpu_kernels too: needs what VPLKIT_GL_TESTS
#                           needs (EGL or OSMesa, glslangValidator); OFF skips it
#   VPLKIT_GL               which headless GL path bench_gpu_kernels takes (support/headless_gl)
#   GLIBC_TUNABLES          default glibc.malloc.mmap_threshold=268435456:...trim_threshold=1073741824:
#                           freed memory stays in the heap, so a "build" benchmark measures the
#                           work, not the kernel's first-touch page faults on fresh mmapped arrays
#                           (docs/results.md, discrete distributions); set it to "" for glibc's
#                           defaults
# Tests are configured (Catch2 must be installed, as for scripts/test.sh) because the GL support
# library is built only with them, but only the benchmark programs are built.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build=${VPLKIT_BENCH_BUILD_DIR:-build/bench}
out=${1:-$build/results}
[ $# -gt 0 ] && shift
reps=${VPLKIT_BENCH_REPS:-3}
min_time=${VPLKIT_BENCH_MIN_TIME:-0.05}
gl=${VPLKIT_BENCH_GL:-ON}
export GLIBC_TUNABLES=${GLIBC_TUNABLES-glibc.malloc.mmap_threshold=268435456:glibc.malloc.trim_threshold=1073741824}

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DVPLKIT_BUILD_BENCHMARKS=ON \
      -DVPLKIT_BUILD_TESTS=ON -DVPLKIT_BUILD_EXAMPLES=OFF -DVPLKIT_GL_TESTS="$gl" >/dev/null
cmake --build "$build" --target vplkit_benchmarks

mkdir -p "$out"
{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "commit: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "compiler: $(${CXX:-c++} --version 2>/dev/null | head -n 1)"
  echo "repetitions: $reps, min time per repetition: $min_time s"
  echo "GLIBC_TUNABLES: ${GLIBC_TUNABLES:-(unset)}"
  echo "load average before the runs: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)"
  lscpu 2>/dev/null | head -n 20 || true
} > "$out/machine.txt"

status=0
for exe in "$build"/tests/bench/bench_*; do
  [ -x "$exe" ] && [ -f "$exe" ] || continue
  name=$(basename "$exe")
  echo "== $name"
  if ! "$exe" --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
       --benchmark_min_time="$min_time" --benchmark_format=console --benchmark_color=false \
       --benchmark_out="$out/$name.json" --benchmark_out_format=json "$@" \
       > "$out/$name.txt" 2> "$out/$name.log"; then
    echo "   FAILED (see $out/$name.log)"
    status=1
  fi
  grep -m1 '^gl:' "$out/$name.log" >> "$out/machine.txt" || true
done

awk -f scripts/bench_to_markdown.awk "$out"/bench_*.json > "$out/results.md"
echo "== results: $out/results.md (machine: $out/machine.txt)"
exit $status
