#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/results.md section 11: every method's image mean against the ground truth (c) with exact
# visibility, on the three scenes. CPU backend (Embree), 96x96, DPRSM 2x128^2, 64^3 voxels (unused
# by exact visibility), patch VPLs (the default), the shadow-ray lit test (the default with exact
# visibility), every method at 1024 samples over seeds 1-8 (image means to a few 0.1 %),
# references (a) the exhaustive patch sum, (b) converged gathering and (c) the exact method at 4096
# directions; once with the default VPL clamp (--dmin 0.01) and once without (--dmin 0: the
# estimand of every method is then the continuous integral, the VPL methods' variance unbounded).
# Point-VPL reference (a) alongside, for the midpoint rule's share; gathering and MIS once more with
# the DPRSM's lit test (--lit-test shadow-map), for the shadow map's share. SCENES_LIST picks scenes.
source "$(dirname "$0")/common.sh"
# Measured before the clamp compensation existed (docs/results/clamp_compensation.md measures it): pinned off, as then.
COMMON=(--backend cpu --visibility exact --size 96x96 --dprsm 128 --voxels 64 --clamp-compensation off)
SEEDS=1,2,3,4,5,6,7,8
for s in ${SCENES_LIST:-cornell open sponza}; do
  mapfile -t sa < <(scene_args "$s")
  for dmin in 0.01 0; do
    "$SVE" "${sa[@]}" "${COMMON[@]}" --dmin "$dmin" --methods global,local,gbg,gather,mis --samples 1024 --seeds "$SEEDS" \
      --references all --ref-dirs 4096 --ref-exact-dirs 4096 --cache-dir "$CACHE" --out "$OUT/ground_truth_${s}_dmin${dmin}"
    "$SVE" "${sa[@]}" "${COMMON[@]}" --dmin "$dmin" --vpl-mode point --methods global --samples 1 --references vplsum,exact \
      --ref-exact-dirs 4096 --cache-dir "$CACHE" --out "$OUT/ground_truth_${s}_dmin${dmin}_point"
  done
  "$SVE" "${sa[@]}" "${COMMON[@]}" --lit-test shadow-map --methods gather,mis --samples 1024 --seeds "$SEEDS" \
    --references gather,exact --ref-dirs 4096 --ref-exact-dirs 4096 --cache-dir "$CACHE" --out "$OUT/ground_truth_${s}_shadow_map"
done
# The default visibility (triangle voxels: geometric normals at the hits, the shadow map) on sponza.
if [[ " ${SCENES_LIST:-cornell open sponza} " == *" sponza "* ]]; then
  mapfile -t sa < <(scene_args sponza)
  "$SVE" "${sa[@]}" --backend cpu --visibility voxels --size 96x96 --dprsm 128 --voxels 64 --methods gather,mis \
    --samples 256 --seeds 1,2 --references gather,exact --ref-dirs 4096 --ref-exact-dirs 4096 --cache-dir "$CACHE" \
    --out "$OUT/ground_truth_sponza_voxels"
fi
