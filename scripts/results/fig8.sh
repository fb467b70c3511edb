#!/bin/bash
# SPDX-License-Identifier: MIT
# Fig. 8 analogue (RMSE against samples), equal-error table and Pareto front, bias/variance:
# every method at samples 1..800, 2 seeds, both references, on each scene. 128x128, DPRSM
# 2x128x128, 64^3 voxels: the exhaustive VPL sum stays affordable (minutes on 2 cores). Every
# reference is computed, the ground truth (c) included. PREFIX names the files (default fig8;
# docs/results.md section 3.1 is PREFIX=fig8c, the run against (c) with the current defaults).
source "$(dirname "$0")/common.sh"
for s in ${SCENES_LIST:-cornell open sponza}; do
  mapfile -t sa < <(scene_args "$s")
  "$SVE" "${sa[@]}" --backend gpu --size 128x128 --dprsm 128 --voxels 64 \
    --methods global,local,gbg,gather,mis,mis-as-published --samples 1,4,16,64,256,800 --seeds 1,2 \
    --ref-dirs 4096 --cache-dir "$CACHE" --references all --out "$OUT/${PREFIX:-fig8}_$s"
done
