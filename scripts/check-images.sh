#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Shows that a change leaves every image bit for bit as it was: builds vplrender at REV (default
# HEAD) in a scratch worktree and from the working tree, renders the matrix of
# scripts/image-manifest.sh with both, and compares the hashes. Exit 0 when all are identical.
# FLAGS go to the working tree's renders only: a default that moved behind a flag is shown to
# reproduce the old default (scripts/check-images.sh f2cf1d5 --visibility paper-voxels).
#   scripts/check-images.sh [REV [FLAGS...]]
set -euo pipefail
cd "$(dirname "$0")/.."
rev=${1:-HEAD}
head_flags=("${@:2}")
sha=$(git rev-parse --short "$rev")
jobs=$(nproc)
base_src="build/check-images/src-$sha"
if [ ! -d "$base_src" ]; then
  git worktree add --detach "$base_src" "$sha" >/dev/null
fi
build_one() {  # source dir, build dir
  cmake -S "$1" -B "$2" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVPLKIT_BUILD_TESTS=OFF \
        -DVPLKIT_BUILD_BENCHMARKS=OFF >/dev/null
  cmake --build "$2" -j"$jobs" --target vplrender >/dev/null
}
echo "check-images: building $sha and the working tree"
build_one "$base_src" "build/check-images/base-$sha"
build_one . build/check-images/head
scripts/image-manifest.sh "build/check-images/base-$sha" "build/check-images/out-$sha" >"build/check-images/$sha.txt"
scripts/image-manifest.sh build/check-images/head build/check-images/out-head ${head_flags[@]+"${head_flags[@]}"} \
  >build/check-images/head.txt
n=$(wc -l <build/check-images/head.txt)
if diff "build/check-images/$sha.txt" build/check-images/head.txt; then
  echo "check-images: all $n images bit-identical to $sha"
else
  echo "check-images: images differ from $sha (lines above: < $sha, > working tree)" >&2
  exit 1
fi
