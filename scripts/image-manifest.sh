#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Renders a fixed matrix of small images (both built-in scenes, every method, both backends, the
# estimator switches) with a built vplrender and prints "sha256  name" for each OpenEXR. Two
# builds that print the same manifest produce bit-identical images; scripts/check-images.sh
# compares a revision against the working tree this way. FLAGS are added to every render (e.g.
# --visibility paper-voxels, to compare with a revision whose default that was).
#   scripts/image-manifest.sh BUILD_DIR [WORK_DIR [FLAGS...]]
set -euo pipefail
build=${1:?usage: image-manifest.sh BUILD_DIR [WORK_DIR]}
exe="$build/examples/vplrender/vplrender"
[ -x "$exe" ] || { echo "image-manifest: no vplrender at $exe" >&2; exit 1; }
work=${2:-$(mktemp -d)}
extra=("${@:3}")
mkdir -p "$work"
small=(--size 48x32 --dprsm 32 --voxels 32 --vpls 16 --dirs 16 --seed 7 --progress never)
render() {  # name, flags...
  local name=$1; shift
  "$exe" "$@" ${extra[@]+"${extra[@]}"} --out "$work/$name.exr" >"$work/$name.log" 2>&1 ||
    { echo "image-manifest: $name failed:" >&2; cat "$work/$name.log" >&2; exit 1; }
  (cd "$work" && sha256sum "$name.exr")
}
for scene in cornell open; do
  for backend in gpu cpu; do
    for m in reference global local gbg gather mis mis-as-published; do
      render "${scene}_${backend}_${m}" --scene "$scene" --backend "$backend" --method "$m" "${small[@]}"
    done
    render "${scene}_${backend}_mis_direct" --scene "$scene" --backend "$backend" --method mis --direct "${small[@]}"
    render "${scene}_${backend}_local_average" --scene "$scene" --backend "$backend" --method local \
      --local-combination average "${small[@]}"
    render "${scene}_${backend}_gbg_paper_eps0" --scene "$scene" --backend "$backend" --method gbg \
      --gbg-accumulator paper --eps 0 "${small[@]}"
    render "${scene}_${backend}_global_binary" --scene "$scene" --backend "$backend" --method global \
      --cdf-search binary "${small[@]}"
  done
  # The default sizes' DPRSM and voxel grid, at a small image.
  render "${scene}_gpu_mis_defaults" --scene "$scene" --method mis --size 64x64 --progress never
done
