#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# docs/results/clamp_compensation.md: the VPL clamp's compensation (docs/math.md, "The clamp's compensation"), before and
# after, against the ground truth (c) = --method exact. CPU backend (Embree), --visibility exact,
# 96x96, DPRSM 2x128^2, 64^3 voxels (the junction band's voxels), patch VPLs, the default dmin (1 %
# of the scene's diagonal) and lit test (the shadow ray); global, local, gbg and ris with
# --clamp-compensation off,on in one process each, so both settings see the same buffers and (c):
#  1. accuracy: 1024 samples, seeds 1-8: each image's mean and its mean over the junction band
#     (pixels within 2 voxels of another surface: examples/speed_vs_error/junction_band.hpp);
#  2. the error curve: 16, 64 and 256 samples, seeds 1-4: relMSE against (c);
#  3. the cost: vplrender's whole-process user CPU time (/usr/bin/time) at 256 VPLs, off and on
#     alternated REPEATS times (default 5), and at 1 VPL (the frame's preparation and the builders,
#     shared by both): the compensation's share of the estimate, (on - off) / (off - prep), median
#     over the pairs (stage wall times are useless on a shared machine, CPU time is not);
#  4. equal time: relMSE of each compensated run at n samples against the clamped series at
#     n (1 + cost) samples, interpolated linearly in log(samples)-log(relMSE) over 16 ... 1024.
# Writes PREFIX_summary.md per scene: per series, the mean over the seeds of the image mean and the
# band mean relative to (c), with the standard error of that mean (from the seeds' spread), the
# mean relMSE and estimate time; and clamp_<scene>_cost.md. SCENES_LIST picks scenes.
source "$(dirname "$0")/common.sh"
# Smaller runs for a busy machine: SIZE (default 96x96), REF_DIRS (4096), ACC_SAMPLES and ACC_SEEDS
# (1024; 1-8), SWEEP_SAMPLES and SWEEP_SEEDS (16,64,256; 1-4), REPEATS.
FRAME=(--backend cpu --visibility exact --size "${SIZE:-96x96}" --dprsm 128 --voxels 64)
COMMON=("${FRAME[@]}" --references exact --ref-exact-dirs "${REF_DIRS:-4096}" --methods global,local,gbg,ris
        --clamp-compensation off,on)
REPEATS=${REPEATS:-5}

# summarize CSV MD: the summary table for one sweep (columns found by name).
summarize() {
  local csv=$1 md=$2
  local exact_mean exact_band
  exact_mean=$(grep -o 'Image means: VPL sum [^,]*, gathering [^,]*, exact [0-9][0-9.]*e[+-][0-9]*' "$md" | sed 's/.*exact //')
  exact_band=$(grep -o 'Junction band ([^)]*): [0-9]* pixels, means: VPL sum [^,]*, gathering [^,]*, exact [0-9][0-9.]*e[+-][0-9]*' "$md" |
               sed 's/.*exact //')
  awk -F, -v em="$exact_mean" -v eb="$exact_band" '
    NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    {
      k = $col["method"] (($col["method"] ~ /^(global|local|gbg|ris)$/ && $col["clamp_compensation"] == "off") ? "-clamped" : "") "|" $col["samples"]
      if (!(k in n)) order[++nk] = k
      n[k]++; m = $col["mean"] / em - 1; b = $col["band_mean"] / eb - 1
      sm[k] += m; sm2[k] += m * m; sb[k] += b; sb2[k] += b * b
      se[k] += $col["estimate_ms"]; sr[k] += $col["relmse_exact"]
    }
    function sem(s, s2, c) { return c > 1 ? sqrt((s2 / c - (s / c) ^ 2) * c / (c - 1) / c) : 0 }
    END {
      printf "(c): image mean %s, band mean %s\n\n", em, eb
      print "| series | samples | seeds | image mean vs (c) | band mean vs (c) | relMSE vs (c) | estimate ms |"
      print "|---|---:|---:|---:|---:|---:|---:|"
      for (i = 1; i <= nk; ++i) {
        k = order[i]; split(k, p, "|"); c = n[k]
        printf "| %s | %s | %d | %+.2f (%.2f) %% | %+.2f (%.2f) %% | %.4e | %.0f |\n", p[1], p[2], c,
               100 * sm[k] / c, 100 * sem(sm[k], sm2[k], c), 100 * sb[k] / c, 100 * sem(sb[k], sb2[k], c), sr[k] / c, se[k] / c
      }
    }' "$csv"
}

# user_seconds ARGS...: vplrender's user CPU time in seconds.
user_seconds() {
  /usr/bin/time -f %U -o "$tmp/time" "$VPLRENDER" "$@" --progress never --out "$tmp/cost.exr" > /dev/null
  cat "$tmp/time"
}

# cost SCENE METHOD: the compensation's share of the estimate's CPU time (see 3. above).
cost() {
  local args=("${sa[@]}" "${FRAME[@]}" --method "$2") prep ratios=() off on
  prep=$(user_seconds "${args[@]}" --vpls 1 --clamp-compensation off)
  for ((k = 0; k < REPEATS; ++k)); do
    off=$(user_seconds "${args[@]}" --vpls 256 --clamp-compensation off)
    on=$(user_seconds "${args[@]}" --vpls 256 --clamp-compensation on)
    ratios+=("$(awk -v a="$on" -v b="$off" -v p="$prep" 'BEGIN { printf "%.4f", (a - b) / (b - p) }')")
  done
  printf '%s\n' "${ratios[@]}" | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'
}

# equal_time SWEEP_CSV FULL_CSV COSTS: the table of 4. above (COSTS: "global=0.1 local=0.1 ...").
equal_time() {
  awk -F, -v costs="$3" '
    BEGIN { n = split(costs, c, " "); for (i = 1; i <= n; ++i) { split(c[i], kv, "="); cost[kv[1]] = kv[2] } }
    FNR == 1 { delete col; for (i = 1; i <= NF; ++i) col[$i] = i; next }
    {
      m = $col["method"]; off = $col["clamp_compensation"] == "off"; n = $col["samples"]
      k = m SUBSEP off SUBSEP n
      if (!(k in cnt)) { if (off) { ns[m]++; smp[m, ns[m]] = n } else { no[m]++; osmp[m, no[m]] = n } }
      cnt[k]++; rel[k] += $col["relmse_exact"]
    }
    END {
      print "| method | cost | samples | relMSE | clamped at samples x (1 + cost) | ratio |"
      print "|---|---:|---:|---:|---:|---:|"
      for (m in cost)
        for (i = 1; i <= no[m]; ++i) {
          n = osmp[m, i]; r_on = rel[m, 0, n] / cnt[m, 0, n]; t = n * (1 + cost[m]); r = -1
          for (j = 1; j < ns[m]; ++j) {
            a = smp[m, j]; b = smp[m, j + 1]
            if (a <= t && t <= b) {
              ra = rel[m, 1, a] / cnt[m, 1, a]; rb = rel[m, 1, b] / cnt[m, 1, b]
              r = exp(log(ra) + (log(t) - log(a)) / (log(b) - log(a)) * (log(rb) - log(ra)))
            }
          }
          if (r < 0) printf "| %s | %+.1f %% | %d | %.4e | - | - |\n", m, 100 * cost[m], n, r_on
          else printf "| %s | %+.1f %% | %d | %.4e | %.4e | %.3f |\n", m, 100 * cost[m], n, r_on, r, r_on / r
        }
    }' "$1" "$2"
}

# PART=dirs: only the directions-per-pixel study (scripts/results/clamp_compensation_dirs.py, its
# settings there): each scene's flags go to it as NAME=FLAGS (separated by the unit separator).
if [[ ${PART:-all} == dirs ]]; then
  args=()
  for s in ${SCENES_LIST:-cornell open sponza}; do
    mapfile -t sa < <(scene_args "$s")
    args+=("$s=$(IFS=$'\x1f'; echo "${sa[*]}")")
  done
  SIZE=${SIZE:-96x96} REF_DIRS=${REF_DIRS:-4096} python3 "$ROOT/scripts/results/clamp_compensation_dirs.py" \
    "$SVE" "$VPLRENDER" "$OUT" "$CACHE" "${args[@]}"
  exit 0
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for s in ${SCENES_LIST:-cornell open sponza}; do
  mapfile -t sa < <(scene_args "$s")
  "$SVE" "${sa[@]}" "${COMMON[@]}" --samples "${ACC_SAMPLES:-1024}" --seeds "${ACC_SEEDS:-1,2,3,4,5,6,7,8}" --cache-dir "$CACHE" \
    --out "$OUT/clamp_${s}"
  summarize "$OUT/clamp_${s}.csv" "$OUT/clamp_${s}.md" > "$OUT/clamp_${s}_summary.md"
  "$SVE" "${sa[@]}" "${COMMON[@]}" --samples "${SWEEP_SAMPLES:-16,64,256}" --seeds "${SWEEP_SEEDS:-1,2,3,4}" --cache-dir "$CACHE" \
    --out "$OUT/clamp_${s}_sweep"
  summarize "$OUT/clamp_${s}_sweep.csv" "$OUT/clamp_${s}_sweep.md" > "$OUT/clamp_${s}_sweep_summary.md"
  costs=""
  for m in global local gbg ris; do costs+="$m=$(cost "$s" "$m") "; done
  {
    echo "Compensation's share of the estimate's CPU time at 256 VPLs (median of $REPEATS pairs): $costs"
    echo
    equal_time "$OUT/clamp_${s}_sweep.csv" "$OUT/clamp_${s}.csv" "$costs"
  } > "$OUT/clamp_${s}_cost.md"
done
