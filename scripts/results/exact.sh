#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/results.md section 7: every method against the ground truth (c) = --method exact, with
# --visibility voxels and --visibility exact, on both built-in scenes and both backends, back to
# back in one run of this script. Sizes: 96x96, DPRSM 2x64^2, 64^3 voxels, 64 samples, references
# at 4096 directions. The GPU sweeps compute only reference (c) (the exhaustive VPL sum through
# llvmpipe's BVH traversal would take long and adds nothing the CPU sweep does not show).
source "$(dirname "$0")/common.sh"
REPEATS=${REPEATS:-3}
for scene in cornell open; do
  for back in cpu gpu; do
    refs=all
    [[ $back == gpu ]] && refs=exact
    for vis in voxels exact; do
      # --clamp-compensation off: as measured, before it existed (the GPU backend has none yet).
      "$SVE" --scene "$scene" --backend "$back" --visibility "$vis" --size 96x96 --dprsm 64 --voxels 64 --clamp-compensation off \
        --methods global,local,gbg,gather,mis --samples 64 --repeats "$REPEATS" --references "$refs" \
        --ref-dirs 4096 --ref-exact-dirs 4096 --cache-dir "$CACHE" --out "$OUT/exact_${scene}_${back}_${vis}"
    done
  done
done
