#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/results.md section 8: point vs patch VPLs (--vpl-mode). With --visibility exact on the CPU
# backend (Embree), 96x96, DPRSM 2x64^2, 64^3 voxels, references at 4096 directions:
#  - the three references, (a) the exhaustive VPL sum in each mode, (b) converged gathering and
#    (c) the exact method, their means and the RMSE between them (PREFIX.md's header line);
#  - global and mis at 64 samples over 4 seeds in each mode: their means against (c) (mis's
#    discretisation bias with point VPLs) and their bias/variance split;
#  - the references' own noise: gather and exact at 4096 directions over 2 seeds (their per-run
#    variance), and the patch VPL sum at two seeds rendered by vplrender (OUT/ref_patch_<scene>_<seed>.exr).
source "$(dirname "$0")/common.sh"
# Measured before the clamp compensation existed (results/clamp_compensation.md measures it): pinned off.
COMMON=(--backend cpu --visibility exact --size 96x96 --dprsm 64 --voxels 64 --clamp-compensation off)
for scene in cornell open; do
  for mode in point patch; do
    "$SVE" --scene "$scene" "${COMMON[@]}" --vpl-mode "$mode" --methods global,mis --samples 64 --seeds 1,2,3,4 \
      --references all --ref-dirs 4096 --ref-exact-dirs 4096 --cache-dir "$CACHE" --out "$OUT/patch_${scene}_${mode}"
  done
  "$SVE" --scene "$scene" "${COMMON[@]}" --methods gather,exact --samples 4096 --seeds 1,2 --references all \
    --ref-dirs 4096 --ref-exact-dirs 4096 --cache-dir "$CACHE" --out "$OUT/patch_${scene}_refnoise"
  for seed in 1 2; do
    "$VPLRENDER" --scene "$scene" "${COMMON[@]}" --method reference --vpl-mode patch --seed "$seed" --progress never \
      --out "$OUT/ref_patch_${scene}_${seed}.exr"
  done
done
