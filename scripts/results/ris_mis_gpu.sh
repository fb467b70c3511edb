#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ris-mis at equal time on the GPU backend, and the GL parity and Vulkan kernel tests, as one run
# for a GPU machine (docs/results.md, "On an NVIDIA H200"). In the device pack
# (../shared/device/pack.sh build/release, of a build configured with -DVPLKIT_TEST_PCH=OFF: the
# tests' precompiled headers, 435 MB, would push the pack past the device's 64 MiB):
#   bash .device/run.sh scripts/results/ris_mis_gpu.sh build/release "$OUT"
# Usage: scripts/results/ris_mis_gpu.sh [--quick] [--no-tests] [--budget SECONDS] BUILD_DIR OUTDIR
#   1. the device (GL renderer and version, nvidia-smi);
#   2. at once: ctest -L 'parity|vulkan' (less the vulkan_bindings CMake scripts and the renderer's
#      image tests, whose many kernel variants each compile cold for 30-40 s), and one small
#      speed_vs_error per scene and method with the settings of part 3, so that the driver compiles
#      every kernel variant before anything is timed (NVIDIA: 30-40 s per variant on a fresh
#      machine; its disk cache serves the later processes);
#   3. per scene (cornell and open with M = 2 and 1, R = 1; sponza M = 2, R = 4: the CPU's
#      allocation), 512x512, the default DPRSM (2x512^2) and visibility (exact), seeds 1 and 2,
#      two repeats (the faster one's time), net relMSE against (c) with 4096 directions:
#      speed_vs_error --methods global --samples 1,4,16,64,256,800 and --methods gather,mis,ris-mis
#      --samples 1,4,16,64,256,512, then scripts/results/equal_time.py at global's 16, 64, 256 and
#      800 VPLs.
# Writes OUTDIR/ris_mis_gpu.md (the device, the test counts, the equal-time tables) and
# OUTDIR/ris_mis_gpu_raw.tar.gz (every CSV, table and log), and prints the summary last.
# --quick: tiny sizes and a few tests, to check the script itself (on llvmpipe).
# --no-tests: leaves out the ctest of part 2 (153 s on the H200; the compiles stay).
# CONFIGS="scene:M:R[:SOURCE] ...": the scenes and their ris-mis settings (default: all three
#   above); SOURCE is the candidate source (flux by default; tiles: --candidate-source tiles, which
#   the CPU measured best on cornell and open with exact visibility, M = 4, R = 1). A scene listed
#   twice has its global sweep once. A source other than flux adds _SOURCE to the run's names.
# Measured on the H200 (docs/results/h200-6044fb0): the compiles and tests 174 s, then per scene
# about 40 s for global and 130 s for gather, mis and ris-mis: all three scenes need ~700 s.
# --budget: the whole run's wall time (default 420 s); a step is cut to what is left of it and one
# that would start with under 20 s left is skipped (runs.tsv says which), so the report is always
# written.
set -u -o pipefail
QUICK=0
RUN_TESTS=1
BUDGET=420
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) QUICK=1 ;;
    --no-tests) RUN_TESTS=0 ;;
    --budget) BUDGET=${2:?--budget SECONDS}; shift ;;
    *) break ;;
  esac
  shift
done
[ $# -eq 2 ] || { echo "usage: $0 [--quick] [--no-tests] [--budget SECONDS] BUILD_DIR OUTDIR" >&2; exit 2; }
BUILD=$(cd "$1" 2>/dev/null && pwd) || { echo "$0: no build directory $1" >&2; exit 2; }
mkdir -p "$2" && OUT=$(cd "$2" && pwd) || exit 2
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SVE=$BUILD/examples/speed_vs_error/speed_vs_error
VR=$BUILD/examples/vplrender/vplrender
for exe in "$SVE" "$VR"; do [ -x "$exe" ] || { echo "$0: $exe is missing" >&2; exit 2; }; done
SCENES=$ROOT/../shared/scenes
RAW=$OUT/raw
mkdir -p "$RAW/logs" "$RAW/sweeps"
CACHE=$(mktemp -d "${TMPDIR:-/tmp}/ris_mis_gpu_cache.XXXXXX") || exit 2
# NVIDIA's shader cache, in a folder this run can write (the default one under $HOME may not be):
# a kernel compiled once (the warm-up, a test's first variant) loads from it afterwards.
mkdir -p "$CACHE/glcache"
export __GL_SHADER_DISK_CACHE=1 __GL_SHADER_DISK_CACHE_SKIP_CLEANUP=1 __GL_SHADER_DISK_CACHE_PATH=$CACHE/glcache
START=$SECONDS
if [ $QUICK -eq 1 ]; then
  SIZE=32x32; GRID=(--dprsm 32 --voxels 16); SEEDS=1; REFDIRS=16
  S_GLOBAL=1,4,16; S_OTHER=1,4,16; BUDGETS=4,16; CONFIGS="cornell:2:1 cornell:2:1:tiles"
  TESTS=(-R '^parity_kernel_params_test|^vulkan_kernels_test:pick_vpls'); JOBS=2
else
  SIZE=512x512; GRID=(); SEEDS=1,2; REFDIRS=4096
  S_GLOBAL=1,4,16,64,256,800; S_OTHER=1,4,16,64,256,512; BUDGETS=16,64,256,800
  CONFIGS=${CONFIGS:-cornell:2:1 open:1:1 sponza:2:4}; TESTS=(); JOBS=12
fi
# scene NAME: the flags of a scene (sponza: the camera and light of docs/results.md)
scene() {
  if [ "$1" = sponza ]; then
    printf '%s\n' --scene "$SCENES/sponza/sponza.obj" --camera -15,2.5,0,5,4.5,0,0,1,0,60 --light 0,11.5,0
  else printf '%s\n' --scene "$1"; fi
}
# bounded NAME LIMIT CMD...: CMD with its output in logs/NAME.log, within LIMIT seconds and what
# is left of the budget; one line in runs.tsv.
bounded() {
  local name=$1 limit=$2 t0 rc left
  shift 2
  left=$((BUDGET - (SECONDS - START) - 10))
  if [ $left -lt 20 ]; then
    printf '%s\tskipped (budget of %s s spent)\t0 s\n' "$name" "$BUDGET" | tee -a "$RAW/runs.tsv"
    return 1
  fi
  [ $limit -gt $left ] && limit=$left
  t0=$SECONDS
  timeout --kill-after=10 "$limit" "$@" > "$RAW/logs/$name.log" 2>&1
  rc=$?
  printf '%s\t%s\t%s s\n' "$name" "$([ $rc -eq 0 ] && echo ok || echo "exit $rc")" $((SECONDS - t0)) | tee -a "$RAW/runs.tsv"
  return $rc
}

# ---- 1. the device ---------------------------------------------------------------------------
bounded device 120 "$VR" --backend gpu --progress never --method global --size 8x8 --dprsm 8 --voxels 4 --vpls 1 \
  --out "$RAW/device.exr"
rm -f "$RAW/device.exr" "$RAW/device.png"
{
  echo "gl: $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["gl_renderer"])' "$RAW/device.json" 2>&1)"
  command -v nvidia-smi > /dev/null && nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv,noheader
  echo "host: $(uname -srm), $(getconf _NPROCESSORS_ONLN) cores"
  echo "commit: ${VPLKIT_COMMIT:-$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)}"
} > "$RAW/device.txt" 2>&1
cat "$RAW/device.txt"

# ---- 2. the tests, and every kernel variant compiled once ------------------------------------
tests_pid=
if [ $RUN_TESTS -eq 1 ]; then
  (cd "$BUILD" && bounded ctest 200 ctest -L 'parity|vulkan' -E '^(vulkan_bindings|renderer_)' "${TESTS[@]}" -j$JOBS \
     --timeout 150 --output-on-failure) &
  tests_pid=$!
else
  echo "ctest	left out (--no-tests)" >> "$RAW/runs.tsv"
  echo "(left out: --no-tests)" > "$RAW/logs/ctest.log"
fi
warm_one() {  # SCENE:M:R:SOURCE:METHOD
  local s m r src meth
  IFS=: read -r s m r src meth <<< "$1"
  mapfile -t sa < <(scene "$s")
  timeout 150 "$SVE" "${sa[@]}" --backend gpu --size 16x16 $GRID_WARM --seeds 1 --repeats 1 --references exact \
    --ref-exact-dirs 4 --ref-noise off --cache-dir "$CACHE/warm" --methods "$meth" --samples 1 --candidates "$m" \
    --candidate-source "$src" --spatial 0 --dirs-per-sample "$r" --out "$CACHE/warm_${s}_${src}_$meth" \
    > "$RAW/logs/warm_${s}_${src}_$meth.log" 2>&1
  echo "warm $s $src $meth: exit $?"
}
export -f warm_one scene
export SVE RAW CACHE SCENES GRID_WARM="${GRID[*]:-}"
# Four at a time, in scene order: the first scene's processes compile, the later ones mostly read
# the driver's cache.
for c in $CONFIGS; do
  IFS=: read -r s m r src <<< "$c"
  for meth in global gather mis ris-mis; do echo "$s:$m:$r:${src:-flux}:$meth"; done
done | xargs -P 4 -I{} bash -c 'warm_one "$1"' _ {}
[ -n "$tests_pid" ] && wait $tests_pid
echo "compiles and tests done at $((SECONDS - START)) s"

# ---- 3. equal time ---------------------------------------------------------------------------
# A scene's global sweep, and its gather and mis series, run with its first configuration only;
# each configuration's table compares its ris-mis with them.
declare -A base_runs=()
for c in $CONFIGS; do
  IFS=: read -r s m r src <<< "$c"
  src=${src:-flux}
  name="M${m}_R${r}"; title="M = $m, R = $r"
  [ "$src" != flux ] && name+="_$src" && title+=", $src"
  mapfile -t sa < <(scene "$s")
  common=("${sa[@]}" --backend gpu --size $SIZE "${GRID[@]}" --seeds $SEEDS --repeats 2 --references exact
          --ref-exact-dirs $REFDIRS --cache-dir "$CACHE")
  methods=ris-mis
  if [ -z "${base_runs[$s]:-}" ]; then
    bounded "sve_${s}_global" 200 "$SVE" "${common[@]}" --methods global --samples $S_GLOBAL \
      --out "$RAW/sweeps/gpu_${s}_global"
    base_runs[$s]="$RAW/sweeps/gpu_${s}_global $RAW/sweeps/gpu_${s}_$name"
    methods=gather,mis,ris-mis
  fi
  bounded "sve_${s}_$name" 240 "$SVE" "${common[@]}" --methods $methods --samples $S_OTHER \
    --candidates $m --candidate-source $src --spatial 0 --dirs-per-sample $r --out "$RAW/sweeps/gpu_${s}_$name"
  runs=()
  for p in ${base_runs[$s]} "$RAW/sweeps/gpu_${s}_$name"; do
    [ -s "$p.csv" ] && [[ " ${runs[*]:-} " != *" $p "* ]] && runs+=("$p")
  done
  { echo "### $s ($title)"; echo
    python3 "$ROOT/scripts/results/equal_time.py" --budgets $BUDGETS "${runs[@]}" 2>&1; echo; } >> "$RAW/equal_time.md"
done

# ---- the report ------------------------------------------------------------------------------
{
  echo "# ris-mis on the GPU backend: $(sed -n 's/^gl: //p' "$RAW/device.txt")"
  echo
  echo '```'
  cat "$RAW/device.txt"
  echo '```'
  echo
  echo "## Tests: ctest -L 'parity|vulkan' -E '^(vulkan_bindings|renderer_)'"
  echo
  echo '```'
  grep -E 'tests passed|tests failed|\*\*\*(Failed|Timeout|Exception)|Not Run' "$RAW/logs/ctest.log" | head -60
  echo '```'
  echo
  echo "## Equal time (net relMSE against (c); budgets: global's time at $BUDGETS VPLs)"
  echo
  cat "$RAW/equal_time.md"
  echo "## Runs"
  echo
  echo '```'
  cat "$RAW/runs.tsv"
  echo "total: $((SECONDS - START)) s"
  echo '```'
} > "$OUT/ris_mis_gpu.md"
rm -rf "$CACHE"
tar -C "$OUT" -czf "$OUT/ris_mis_gpu_raw.tar.gz" raw && rm -rf "$RAW"
echo
cat "$OUT/ris_mis_gpu.md"
