#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/results.md section 11: every method's image mean against the ground truth (c) with exact
# visibility, on the three scenes. CPU backend (Embree), 96x96, DPRSM 2x128^2, 64^3 voxels (unused
# by exact visibility), patch VPLs (the default), every method at 64 samples over seeds 1 and 2,
# references (a) the exhaustive patch sum, (b) converged gathering and (c) the exact method at
# 4096 directions; once with the default VPL clamp (--dmin 0.01) and once without (--dmin 0: the
# estimand of every method is then the continuous integral, the VPL methods' variance unbounded).
# Point-VPL reference (a) alongside, for the midpoint rule's share. SCENES_LIST picks scenes.
source "$(dirname "$0")/common.sh"
COMMON=(--backend cpu --visibility exact --size 96x96 --dprsm 128 --voxels 64)
for s in ${SCENES_LIST:-cornell open sponza}; do
  mapfile -t sa < <(scene_args "$s")
  for dmin in 0.01 0; do
    "$SVE" "${sa[@]}" "${COMMON[@]}" --dmin "$dmin" --methods global,local,gbg,gather,mis --samples 64 --seeds 1,2 \
      --references all --ref-dirs 4096 --ref-exact-dirs 4096 --cache-dir "$CACHE" --out "$OUT/ground_truth_${s}_dmin${dmin}"
    "$SVE" "${sa[@]}" "${COMMON[@]}" --dmin "$dmin" --vpl-mode point --methods global --samples 1 --references vplsum,exact \
      --ref-exact-dirs 4096 --cache-dir "$CACHE" --out "$OUT/ground_truth_${s}_dmin${dmin}_point"
  done
done
