#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The project's speed and correctness on the machine's GPU, as one report (docs/renderer.md,
# "GPU report"). Usage:
#   scripts/gpu-report.sh [--quick] [--no-tests] [--budget SECONDS] BUILD_DIR OUTDIR
# BUILD_DIR: a build of this checkout with the examples and the tests (Release for numbers that
# mean something; ../shared/device/pack.sh makes one). In the device pack:
#   bash .device/run.sh scripts/gpu-report.sh build/gpu "$OUT"
# Runs, each bounded by `timeout` and all together by the time budget (default 480 s; a run that
# would start after it is recorded as skipped):
#   1. the device: GL_RENDERER / GL_VERSION (the headless context of vplrender), the Vulkan device
#      (vulkan_kernels_test), nvidia-smi when present, the host and the build type;
#   2. the --frames benchmark: cornell at 512x512 with 16 VPLs (global; and mis with 16 directions)
#      on the GPU backend, and the CPU backend for comparison;
#   3. ctest -L vulkan, then ctest -L parity -LE vulkan (the slow ones included);
#   4. the stage profile: one vplrender frame per size, VPL count, voxel resolution, visibility and
#      method (the runs of ../shared/evidence/nvidia-h200/stages);
#   5. the Table 1 analogue: speed_vs_error --paper --backend gpu on cornell, open and sponza
#      (global, local, gbg, mis at 800 samples, 3 repeats; gbg with 16 directions), one run per
#      scene and method.
# Writes OUTDIR/gpu-report.md (the tables, the device named) and OUTDIR/gpu-report-raw.tar.gz (every
# JSON report, CSV and log; no images), and prints a short summary table last.
# --no-tests: leaves out part 3 (the ctest labels), for a speed-only report.
# --quick: tiny sizes, few frames and a handful of tests, for a check of the script itself (the
# test renderer_gpu_report_quick runs it on llvmpipe).
set -u -o pipefail

usage() { echo "usage: $0 [--quick] [--no-tests] [--budget SECONDS] BUILD_DIR OUTDIR" >&2; exit 2; }
QUICK=0
TESTS=1
BUDGET=480
ARGS=()
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) QUICK=1 ;;
    --no-tests) TESTS=0 ;;
    --budget) [ $# -ge 2 ] || usage; BUDGET=$2; shift ;;
    -h|--help) sed -n '3,26p' "$0"; exit 0 ;;
    -*) echo "$0: unknown option $1" >&2; usage ;;
    *) ARGS+=("$1") ;;
  esac
  shift
done
[ ${#ARGS[@]} -eq 2 ] || usage
case "$BUDGET" in ''|*[!0-9]*) echo "$0: --budget: expected seconds, got '$BUDGET'" >&2; exit 2 ;; esac
BUILD=$(cd "${ARGS[0]}" 2>/dev/null && pwd) || { echo "$0: no build directory ${ARGS[0]}" >&2; exit 2; }
OUT=${ARGS[1]}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
VR=$BUILD/examples/vplrender/vplrender
SVE=$BUILD/examples/speed_vs_error/speed_vs_error
TOOL=$BUILD/examples/vplrender/gpu_report_tables
VK=$BUILD/tests/vulkan/vulkan_kernels_test
for exe in "$VR" "$SVE" "$TOOL"; do
  [ -x "$exe" ] || { echo "$0: $exe is missing: build the examples in $BUILD" >&2; exit 2; }
done
mkdir -p "$OUT" || exit 2
OUT=$(cd "$OUT" && pwd)
RAW=$(mktemp -d "${TMPDIR:-/tmp}/gpu-report.XXXXXX") || exit 2
trap 'rm -rf "$RAW" "${GLCACHE:-}"' EXIT
mkdir -p "$RAW/device" "$RAW/frames" "$RAW/profile" "$RAW/table1" "$RAW/tests" "$RAW/logs"
SCENES=$ROOT/../shared/scenes
START=$SECONDS
# NVIDIA's shader cache, in a folder this run can write (the default one under $HOME may not be):
# the parity programs' [ftz-daz] and [fma] entries compile the same kernels again.
GLCACHE=$(mktemp -d "${TMPDIR:-/tmp}/gpu_report_glcache.XXXXXX") || exit 2
export __GL_SHADER_DISK_CACHE=1 __GL_SHADER_DISK_CACHE_SKIP_CLEANUP=1 __GL_SHADER_DISK_CACHE_PATH=$GLCACHE

# run NAME LIMIT_S CMD...: runs CMD with its output in logs/NAME.log, bounded by LIMIT_S and by
# what is left of the budget; one line per run in runs.tsv (name, status, wall s, command).
run() {
  local name=$1 limit=$2 left status t0 rc
  shift 2
  left=$((BUDGET - (SECONDS - START)))
  if [ "$left" -lt 5 ]; then
    printf '%s\tskipped (time budget of %s s spent)\t0\t%s\n' "$name" "$BUDGET" "$*" >> "$RAW/runs.tsv"
    echo "  $name: skipped (time budget spent)"
    return 1
  fi
  [ "$limit" -gt "$left" ] && limit=$left
  t0=$(date +%s%N)
  timeout --kill-after=10 "$limit" "$@" > "$RAW/logs/$name.log" 2>&1
  rc=$?
  local tenths=$((($(date +%s%N) - t0) / 100000000))
  local wall=$((tenths / 10)).$((tenths % 10))
  case $rc in
    0) status=ok ;;
    124|137) status="timed out after $limit s" ;;
    *) status="failed (exit $rc)" ;;
  esac
  printf '%s\t%s\t%s\t%s\n' "$name" "$status" "$wall" "$*" >> "$RAW/runs.tsv"
  echo "  $name: $status (${wall} s)"
  [ $rc -eq 0 ]
}

# vplrender with its outputs in DIR/NAME.{exr,png,json}; the images are removed (the JSON stays).
render() {
  local dir=$1 name=$2 limit=$3
  shift 3
  run "$name" "$limit" "$VR" --progress never --out "$RAW/$dir/$name.exr" "$@"
  rm -f "$RAW/$dir/$name.exr" "$RAW/$dir/$name.png"
}

echo "gpu-report: $([ $QUICK -eq 1 ] && echo 'quick, ')budget $BUDGET s, build $BUILD"

# ---- 1. the device --------------------------------------------------------------------------------
echo "device:"
render device device 60 --method global --size 8x8 --dprsm 8 --voxels 4 --vpls 1
if [ -x "$VK" ]; then
  run vulkan_device 60 "$VK" "pick_vpls.comp (the minimal example)*"
  grep -m1 '^vulkan: ' "$RAW/logs/vulkan_device.log" > "$RAW/device/vulkan.txt" ||
    { echo "vulkan: none ($(tail -n 3 "$RAW/logs/vulkan_device.log" | tr '\n' ' '))" > "$RAW/device/vulkan.txt"; }
else
  echo "vulkan: not built (no $VK)" > "$RAW/device/vulkan.txt"
fi
if command -v nvidia-smi > /dev/null 2>&1; then
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv,noheader \
    > "$RAW/device/nvidia_smi.txt" 2>&1 || true
fi
{
  echo "host: $(uname -srm)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //') x $(getconf _NPROCESSORS_ONLN 2>/dev/null)"
  echo "build: $(grep -m1 '^CMAKE_BUILD_TYPE:' "$BUILD/CMakeCache.txt" 2>/dev/null | sed 's/.*=//') ($BUILD)"
  echo "commit: $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo 'unknown (no git checkout)')"
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "mode: $([ $QUICK -eq 1 ] && echo quick || echo full), budget $BUDGET s"
} > "$RAW/device/host.txt"
sed 's/^/  /' "$RAW/device/vulkan.txt"

if [ $QUICK -eq 1 ]; then
  FR_SIZE=48x32; FR_N=3; FR_CPU_N=2; SMALL=(--dprsm 16 --voxels 16)
else
  FR_SIZE=512x512; FR_N=60; FR_CPU_N=5; SMALL=()
fi

# ---- 2. frames ------------------------------------------------------------------------------------
echo "frames:"
render frames fr_gpu_global_v16 120 --backend gpu --scene cornell --size $FR_SIZE "${SMALL[@]}" --method global --vpls 16 --frames $FR_N
render frames fr_gpu_mis_v16 120 --backend gpu --scene cornell --size $FR_SIZE "${SMALL[@]}" --method mis --vpls 16 --dirs 16 --frames $FR_N
render frames fr_cpu_global_v16 120 --backend cpu --scene cornell --size $FR_SIZE "${SMALL[@]}" --method global --vpls 16 --frames $FR_CPU_N

# ---- 3. the Vulkan and parity labels -------------------------------------------------------------
echo "tests:"
if [ $TESTS -eq 1 ]; then
  if [ $QUICK -eq 1 ]; then VK_SELECT=(-R 'pick_vpls'); P_SELECT=(-R '^parity_kernel_params_test'); else VK_SELECT=(); P_SELECT=(); fi
  JOBS=$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)
  IN_BUILD=(bash -c 'cd "$0" && exec "$@"' "$BUILD")  # ctest runs in the build directory
  run ctest_vulkan 120 "${IN_BUILD[@]}" ctest -L vulkan "${VK_SELECT[@]}" -j"$JOBS" --timeout 100 --output-on-failure
  cp "$RAW/logs/ctest_vulkan.log" "$RAW/tests/vulkan.log"
  # The parity label without the Vulkan tests (run above), the slow ones included.
  run ctest_parity 150 "${IN_BUILD[@]}" ctest -L parity -LE vulkan "${P_SELECT[@]}" -j"$JOBS" --timeout 100 --output-on-failure
  cp "$RAW/logs/ctest_parity.log" "$RAW/tests/parity.log"
else
  echo "  left out (--no-tests)"
fi

# ---- 4. the stage profile -------------------------------------------------------------------------
echo "stage profile:"
SPONZA=(--scene "$SCENES/sponza/sponza.obj" --light 0,11.5,0 --camera -15,2.5,0,5,4.5,0,0,1,0,60)
if [ $QUICK -eq 1 ]; then
  render profile p_warm 60 --backend gpu --method global --vpls 4 --size 32x32 --dprsm 16 --voxels 16
  render profile p_s64 60 --backend gpu --method global --vpls 8 --size 64x64 --dprsm 16 --voxels 16
  render profile p_exactvis 60 --backend gpu --method global --vpls 8 --size 64x64 --dprsm 16 --voxels 16 --visibility exact
  render profile p_cpu 60 --backend cpu --method global --vpls 8 --size 64x64 --dprsm 16 --voxels 16
else
  render profile p_warm 30 --backend gpu --method global --vpls 4 --size 64x64
  for s in 256 512 1024; do render profile p_s$s 30 --backend gpu --method global --vpls 64 --size ${s}x$s; done
  for v in 16 256; do render profile p_v$v 30 --backend gpu --method global --vpls $v; done
  render profile p_point 30 --backend gpu --method global --vpls 64 --vpl-mode point
  render profile p_papervox 30 --backend gpu --method global --vpls 64 --visibility paper-voxels
  for x in 32 256; do render profile p_vox$x 30 --backend gpu --method global --vpls 64 --voxels $x; done
  render profile p_exactvis 30 --backend gpu --method global --vpls 64 --visibility exact
  render profile p_gather64 30 --backend gpu --method gather --dirs 64
  render profile p_exact64 30 --backend gpu --method exact --dirs 64
  render profile p_sp_global 60 --backend gpu --method global --vpls 64 "${SPONZA[@]}"
  render profile p_sp_exactvis 60 --backend gpu --method global --vpls 64 --visibility exact "${SPONZA[@]}"
  render profile p_cpu 60 --backend cpu --method global --vpls 64
fi

# ---- 5. the Table 1 analogue ----------------------------------------------------------------------
# One speed_vs_error per scene and method (a method that runs out of time loses only its own
# row); the references are cached per scene. Last, so that a spent budget cuts this first.
echo "Table 1 analogue:"
CACHE=$RAW/sve_cache
# t1 SCENE_NAME METHOD LIMIT [ARGS...]: table1/table1_<scene>_<method>.csv
t1() {
  local sc=$1 m=$2 limit=$3
  shift 3
  run t1_${sc}_$m "$limit" "$SVE" --paper --backend gpu "$@" --cache-dir "$CACHE" --out "$RAW/table1/table1_${sc}_$m"
}
if [ $QUICK -eq 1 ]; then
  Q=(--scene cornell --size 48x32 --dprsm 16 --voxels 16 --samples 4 --ref-dirs 16 --repeats 1 --references gather)
  t1 cornell global 120 "${Q[@]}" --methods global
  t1 cornell gbg16 120 "${Q[@]}" --dirs 4 --methods gbg
else
  for sc in cornell open sponza; do
    if [ $sc = sponza ]; then S=("${SPONZA[@]}"); else S=(--scene $sc); fi
    T=("${S[@]}" --samples 800 --repeats 3 --references gather)
    for m in global local gbg; do t1 $sc $m 25 "${T[@]}" --methods $m; done
    t1 $sc gbg16 20 "${T[@]}" --dirs 16 --methods gbg
    t1 $sc mis 30 "${T[@]}" --methods mis
  done
fi
rm -f "$RAW"/table1/*.svg

# ---- the report -----------------------------------------------------------------------------------
rm -rf "$CACHE"
elapsed=$((SECONDS - START))
echo "total: $elapsed s" >> "$RAW/device/host.txt"
"$TOOL" "$RAW" "$OUT/gpu-report.md" "gpu-report-raw.tar.gz" > "$RAW/summary.txt" || { echo "$0: the report tool failed" >&2; cat "$RAW/summary.txt" >&2; exit 1; }
tar -C "$RAW" -czf "$OUT/gpu-report-raw.tar.gz" --exclude='./sve_cache' . || { echo "$0: cannot write the archive" >&2; exit 1; }
echo
cat "$RAW/summary.txt"
