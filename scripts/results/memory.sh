#!/bin/bash
# SPDX-License-Identifier: MIT
# Memory per method at the paper's parameters: the GPU buffers each estimator holds at its peak
# (beyond the shared G-buffer/DPRSM/voxel read-backs) and the process's peak RSS, one vplrender
# process per method so the RSS is the method's own. Memory does not depend on the sample count,
# so the runs use 8 VPLs / 8 directions to stay short (reference is left out: at 2x512^2 VPLs per
# pixel it runs for hours; it holds nothing beyond the shared buffers).
source "$(dirname "$0")/common.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
s=${SCENE:-cornell}
mapfile -t sa < <(scene_args "$s")
{
  echo "| method | backend | GPU buffers, estimator peak (MiB) | GPU, prepare stages peak (MiB) | host peak RSS (MiB) |"
  echo "|---|---|---:|---:|---:|"
  for b in gpu cpu; do
    for m in global local gbg gather mis mis-as-published; do
      "$VPLRENDER" "${sa[@]}" --paper --vpls 8 --dirs 8 --method $m --backend $b --progress never \
        --out "$tmp/$m.exr" > /dev/null
      j="$tmp/$m.json"
      get() { sed -n "s/.*\"$1\": \\([0-9-]*\\).*/\\1/p" "$j" | head -1; }
      awk -v m=$m -v b=$b -v e="$(get gpu_peak_bytes_estimator)" -v p="$(get gpu_peak_bytes_prepare)" \
          -v r="$(get host_peak_rss_bytes)" \
          'BEGIN { printf "| %s | %s | %.1f | %.1f | %.1f |\n", m, b, e/1048576, p/1048576, r/1048576 }'
    done
  done
} > "$OUT/memory_$s.md"
cat "$OUT/memory_$s.md"
