#!/bin/bash
# SPDX-License-Identifier: MIT
# Our departures from the paper, measured in the renderer (docs/results.md, section 4), at the
# Fig. 8 sizes so the exhaustive VPL sum (cached by fig8.sh) is the reference:
#   local-CDF combination balance vs average (eps 0.05 and 0), the two GBG accumulators,
#   defensive eps 0..0.5, guide table vs binary search (timing, alternated, 3 repeats each).
# mis vs mis-as-published comes from fig8.sh's bias/variance files.
source "$(dirname "$0")/common.sh"
seeds=1,2,3,4
# One sweep per setting into $OUT/departures_runs; merged into $OUT/dep_<kind>.csv and
# $OUT/dep_<kind>_bias_variance.csv at the end (the switch values are columns of both).
RUNS=$OUT/departures_runs
mkdir -p "$RUNS"
for s in ${SCENES_LIST:-cornell open sponza}; do
  mapfile -t sa < <(scene_args "$s")
  run() { "$SVE" "${sa[@]}" --backend gpu --size 128x128 --dprsm 128 --voxels 64 --ref-dirs 4096 \
            --cache-dir "$CACHE" "$@"; }
  for e in 0.05 0; do
    for c in balance average; do
      run --methods local --samples 4,16,64,256 --seeds $seeds --references vplsum --eps $e \
          --local-combination $c --out "$RUNS/dep_local_${c}_eps${e}_$s"
    done
  done
  for a in gathering paper; do
    run --methods gbg,mis --samples 16,64,256 --seeds $seeds --references both --gbg-accumulator $a \
        --out "$RUNS/dep_accumulator_${a}_$s"
  done
  for e in 0 0.05 0.1 0.25 0.5; do
    run --methods global,gbg --samples 64 --seeds $seeds --references vplsum --eps $e --out "$RUNS/dep_eps${e}_$s"
  done
  for round in 1 2; do
    for c in guide binary; do
      run --methods global,gbg,mis --samples 256 --seeds 1 --repeats 3 --references vplsum --cdf-search $c \
          --out "$RUNS/dep_search_${c}_r${round}_$s"
    done
  done
done
for kind in local accumulator eps search; do
  for suffix in "" _bias_variance; do
    files=$(ls "$RUNS"/dep_${kind}*.csv 2>/dev/null | grep -E "_(cornell|open|sponza)${suffix}\.csv$" || true)
    [[ -n $files ]] || continue
    # Header once, then every row.
    awk 'FNR == 1 && NR != 1 { next } { print }' $files > "$OUT/dep_${kind}${suffix}.csv"
  done
done
echo "wrote $OUT/dep_{local,accumulator,eps,search}{,_bias_variance}.csv (per-run files in $RUNS)"
