#!/bin/bash
# SPDX-License-Identifier: MIT
# ris-mis with presampled candidates at equal time (docs/results/ris_cornell_cpu.md, "Presampled
# candidates"): per scene one baseline run of global, gather and mis, then ris-mis runs with M
# candidates per RIS sample drawn directly (P = 0) or from a pool of P per frame
# (--candidate-pool), net relMSE against (c), CPU backend at vplrender's default DPRSM (2x512^2)
# and voxels (128^3); then scripts/results/equal_time.py's table at global's 16-, 64- and 256-VPL
# times, each run's ris-mis against the best other method. CONFIGS: "scene:M:P[:R]" entries (R
# gathering directions per RIS sample, default 1); SEEDS, SAMPLES as the sweep's. cornell and open at 96x96, sponza at 64x64. Gathering's series
# goes on to GATHER_SAMPLES (default 512,1024,2048) in the same baseline CSV, so that it reaches
# global's times measured instead of carried there at 1/t (which ignores its floor). About 8 min per
# ris-mis run and 10 per baseline on 2 cores. EXTRA_ARGS go to every speed_vs_error run (e.g.
# EXTRA_ARGS="--voxel-contract exact").
source "$(dirname "$0")/common.sh"
CONFIGS=${CONFIGS:-open:1:0 open:2:0 open:2:16384 open:8:16384 open:16:16384}
common=(--backend cpu --seeds "${SEEDS:-1,2}" --references exact --ref-exact-dirs 4096 --cache-dir "$CACHE"
        --repeats 1 --candidate-source flux --spatial 0)
read -r -a extra <<< "${EXTRA_ARGS-}"
common+=("${extra[@]}")
samples=(--samples "${SAMPLES:-1,4,16,64,256}")
size_of() { [[ $1 == sponza ]] && echo 64x64 || echo 96x96; }
scenes=$(for c in $CONFIGS; do echo "${c%%:*}"; done | awk '!seen[$0]++')
for s in $scenes; do
  mapfile -t sa < <(scene_args "$s")
  if [[ ! -f $OUT/pool_${s}_base.csv ]]; then
    "$SVE" "${sa[@]}" --size "$(size_of "$s")" "${common[@]}" "${samples[@]}" --methods global,gather,mis \
      --out "$OUT/pool_${s}_base"
    if [[ -n ${GATHER_SAMPLES-512,1024,2048} ]]; then
      "$SVE" "${sa[@]}" --size "$(size_of "$s")" "${common[@]}" --methods gather \
        --samples "${GATHER_SAMPLES-512,1024,2048}" --out "$OUT/pool_${s}_gather_more"
      tail -n +2 "$OUT/pool_${s}_gather_more.csv" >> "$OUT/pool_${s}_base.csv"
    fi
  fi
done
for c in $CONFIGS; do
  IFS=: read -r s m p r <<< "$c"
  r=${r:-1}
  mapfile -t sa < <(scene_args "$s")
  "$SVE" "${sa[@]}" --size "$(size_of "$s")" "${common[@]}" "${samples[@]}" --methods ris-mis --candidates "$m" \
    --candidate-pool "$p" --dirs-per-sample "$r" --out "$OUT/pool_${s}_M${m}_P${p}_R${r}"
done
for s in $scenes; do
  echo "== $s"
  mapfile -t runs < <(ls "$OUT"/pool_"$s"_*.csv | grep -v -e _bias_variance -e _gather_more)
  python3 "$ROOT/scripts/results/equal_time.py" --budgets "${BUDGETS:-16,64,256}" "${runs[@]}"
done
