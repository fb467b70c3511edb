#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/results/clamp_compensation.md, "The crease rule in every gathering strategy": gather, mis
# and exact on cornell and open at 48x48 (DPRSM 2x128^2, 64^3 voxels, exact visibility), CPU and
# GPU backends. Per scene and backend:
#  - vplrender images (gather --dirs 256, mis --vpls 64 --dirs 64, exact --dirs 1024, seed 1) and
#    their means over the image, its two diagonals (on cornell at 48x48 they run through pixel
#    centres on the box's creases) and the rest (exr_region_means.py);
#  - speed_vs_error's image and junction-band means of gather (--dirs 256) and mis (--vpls 256
#    --dirs 256) at 256 samples (2 seeds)
#    against (c) = --method exact at 1024 directions (its own cache: the references change with
#    the rule).
# BUILD as in common.sh (a build with the examples). speed_vs_error's CSV/MD land in
# OUT/crease_<scene>_<backend>_sve*, the images (EXR, PNG, JSON) in IMAGES (default
# build/crease_rule). About 5 minutes on a 2-core machine.
source "$(dirname "$0")/common.sh"
CACHE=${CACHE_CREASE:-$ROOT/build/crease_rule_cache}
IMAGES=${IMAGES:-$ROOT/build/crease_rule}
mkdir -p "$CACHE" "$IMAGES"
FRAME=(--size 48x48 --dprsm 128 --voxels 64 --visibility exact --progress never)
for scene in ${SCENES_LIST:-cornell open}; do
  for backend in ${BACKENDS:-cpu gpu}; do
    p=$IMAGES/crease_${scene}_${backend}
    "$VPLRENDER" --scene "$scene" --backend "$backend" "${FRAME[@]}" --method gather --dirs 256 --out "${p}_gather.exr" > /dev/null
    "$VPLRENDER" --scene "$scene" --backend "$backend" "${FRAME[@]}" --method mis --vpls 64 --dirs 64 --out "${p}_mis.exr" > /dev/null
    "$VPLRENDER" --scene "$scene" --backend "$backend" "${FRAME[@]}" --method exact --dirs 1024 --out "${p}_exact.exr" > /dev/null
    python3 "$ROOT/scripts/results/exr_region_means.py" "${p}_gather.exr" "${p}_mis.exr" "${p}_exact.exr"
    "$SVE" --scene "$scene" --backend "$backend" --size 48x48 --dprsm 128 --voxels 64 --visibility exact \
      --methods gather,mis --samples 256 --seeds 1,2 --references exact --ref-exact-dirs 1024 \
      --cache-dir "$CACHE" --out "$OUT/crease_${scene}_${backend}_sve" > /dev/null
    grep -o 'Junction band ([^)]*): [0-9]* pixels, means: [^|]*' "$OUT/crease_${scene}_${backend}_sve.md" | head -1
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
             { printf "%s seed %s: image mean %s, band mean %s\n", $col["method"], $col["seed"], $col["mean"], $col["band_mean"] }' \
      "$OUT/crease_${scene}_${backend}_sve.csv"
  done
done
