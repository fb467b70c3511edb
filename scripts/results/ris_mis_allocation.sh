#!/bin/bash
# SPDX-License-Identifier: MIT
# ris-mis's sample allocation at equal time (docs/results.md, "Two candidates, and gathering's share
# set by the scene"): per scene, ris-mis with M candidates and R gathering directions per RIS sample
# beside global, gather and mis (mis at the same R), net relMSE against (c), CPU backend; then
# scripts/results/equal_time.py's table at global's 16-, 64-, 256- and 800-VPL times. CONFIGS:
# "scene:M:R" entries (default: the settings of the results table); SEEDS, SAMPLES as the sweep's.
# cornell and open at 96x96, sponza at 64x64; DPRSM 2x128^2, 64^3 voxels. About 40 min on 2 cores.
source "$(dirname "$0")/common.sh"
CONFIGS=${CONFIGS:-cornell:2:1 cornell:1:1 open:2:1 open:1:1 sponza:2:4 sponza:1:4}
for c in $CONFIGS; do
  IFS=: read -r s m r <<< "$c"
  mapfile -t sa < <(scene_args "$s")
  size=96x96; [[ $s == sponza ]] && size=64x64
  "$SVE" "${sa[@]}" --backend cpu --size $size --dprsm 128 --voxels 64 --seeds "${SEEDS:-1,2,3,4}" \
    --references exact --ref-exact-dirs 4096 --cache-dir "$CACHE" --repeats 1 \
    --methods global,gather,mis,ris-mis --samples "${SAMPLES:-1,4,16,64,256,800,1024}" \
    --candidates "$m" --candidate-source flux --spatial 0 --dirs-per-sample "$r" \
    --out "$OUT/alloc_${s}_M${m}_R${r}"
done
budgets=16,64,256,800
for s in $(for c in $CONFIGS; do echo "${c%%:*}"; done | awk '!seen[$0]++'); do
  echo "== $s"
  mapfile -t runs < <(ls "$OUT"/alloc_"$s"_M*_R*.csv | grep -v _bias_variance)
  python3 "$ROOT/scripts/results/equal_time.py" --budgets "${BUDGETS:-$budgets}" "${runs[@]}"
done
