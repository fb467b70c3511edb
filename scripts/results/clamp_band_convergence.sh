#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/results/clamp_compensation.md, "open: global's junction band is a heavy tail": global's
# junction band on `open` against the exhaustive clamped VPL sum (reference (a)) and (c) =
# --method exact, at 256 (64 seeds), 4096 (16) and 16384 (8) samples with the clamp's
# compensation off, and at 4096 (16 seeds) with it on. CPU backend, 48x48, DPRSM 2x128^2, 64^3
# voxels, exact visibility (the frame of clamp_compensation.sh at SIZE=48x48). Prints, per series,
# the band mean relative to the VPL sum and to (c): mean over the seeds, its standard error, the
# median, min / max and one run's standard deviation. Cost on a 2-core machine: about 15 minutes.
source "$(dirname "$0")/common.sh"
SCENE=${SCENE:-open}
BASE=(--scene "$SCENE" --backend cpu --visibility exact --size "${SIZE:-48x48}" --dprsm 128 --voxels 64
      --references vplsum,exact --ref-exact-dirs "${REF_DIRS:-1024}" --methods global --cache-dir "$CACHE")
seeds() { seq -s, 1 "$1"; }

# summarize CSV MD: one line per (clamp_compensation, samples); the references from MD's header.
summarize() {
  local csv=$1 md=$2 vpl exact
  vpl=$(grep -o 'means: VPL sum [0-9][0-9.]*e[+-][0-9]*' "$md" | tail -1 | sed 's/.*sum //')
  exact=$(grep -o 'Junction band ([^)]*): [0-9]* pixels, means: VPL sum [^,]*, gathering [^,]*, exact [0-9][0-9.]*e[+-][0-9]*' "$md" |
          sed 's/.*exact //')
  awk -F, -v vs="$vpl" -v ex="$exact" '
    NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    {
      k = $col["clamp_compensation"] " " $col["samples"]
      if (!(k in n)) order[++nk] = k
      i = ++n[k]; v[k, i] = 100 * ($col["band_mean"] / vs - 1); c[k, i] = 100 * ($col["band_mean"] / ex - 1)
    }
    END {
      printf "band: VPL sum %s (compensation as the last series), (c) %s\n", vs, ex
      print "| compensation samples | seeds | vs VPL sum: mean (se) | median | min / max | sd of one run | vs (c): mean (se) |"
      for (j = 1; j <= nk; ++j) {
        k = order[j]; m = n[k]; s = s2 = t = t2 = 0
        for (i = 1; i <= m; ++i) { a[i] = v[k, i]; s += a[i]; s2 += a[i] ^ 2; t += c[k, i]; t2 += c[k, i] ^ 2 }
        for (i = 2; i <= m; ++i) for (q = i; q > 1 && a[q] < a[q - 1]; --q) { x = a[q]; a[q] = a[q - 1]; a[q - 1] = x }
        med = m % 2 ? a[(m + 1) / 2] : (a[m / 2] + a[m / 2 + 1]) / 2
        sd = m > 1 ? sqrt((s2 - s * s / m) / (m - 1)) : 0; sdc = m > 1 ? sqrt((t2 - t * t / m) / (m - 1)) : 0
        printf "| %s | %d | %+.2f (%.2f) %% | %+.2f %% | %+.1f / %+.1f %% | %.2f %% | %+.2f (%.2f) %% |\n",
               k, m, s / m, sd / sqrt(m), med, a[1], a[m], sd, t / m, sdc / sqrt(m)
      }
    }' "$csv"
}

run() {  # run NAME COMPENSATION SAMPLES SEEDS
  "$SVE" "${BASE[@]}" --clamp-compensation "$2" --samples "$3" --seeds "$(seeds "$4")" --out "$OUT/band_${SCENE}_$1" > /dev/null
  summarize "$OUT/band_${SCENE}_$1.csv" "$OUT/band_${SCENE}_$1.md"
}
run g256 off 256 "${SEEDS_256:-64}"
run g4096 off 4096 "${SEEDS_4096:-16}"
run g16384 off 16384 "${SEEDS_16384:-8}"
run gc4096 on 4096 "${SEEDS_4096:-16}"
