#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# SPDX licence identifiers: every source file of ours carries one (LICENSE is MIT).
#   scripts/spdx.sh           add the line where it is missing
#   scripts/spdx.sh --check   list the files without one and fail (ctest packaging_spdx_headers)
# single_include/ is generated (its generator writes the line once at the top); test data and
# fixtures whose line numbers a test checks (tests/packaging/layers_fixture),
# corpora, images and Markdown carry none.
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
[ "${1:-}" = "--check" ] && check=1
tag='SPDX-License-Identifier: MIT'
missing=0
while IFS= read -r f; do
  [ -f "$f" ] || continue
  head -n 3 "$f" | grep -q "$tag" && continue
  if [ $check -eq 1 ]; then echo "no SPDX line: $f"; missing=1; continue; fi
  case "$f" in
    *.sh|*.cmake|*CMakeLists.txt|*.in|.ci/*) line="# $tag" ;;
    *) line="// $tag" ;;
  esac
  tmp="$f.spdx.$$"
  if head -n 1 "$f" | grep -q '^#!'; then
    { head -n 1 "$f"; echo "$line"; tail -n +2 "$f"; } > "$tmp"
  else
    { echo "$line"; cat "$f"; } > "$tmp"
  fi
  chmod --reference="$f" "$tmp" && mv "$tmp" "$f"
done < <(git ls-files -- '*.cpp' '*.hpp' '*.h' '*.glsl' '*.comp' '*.cmake' '*.sh' \
           '*CMakeLists.txt' '.ci/run' ':!single_include/**' ':!tests/fuzz/corpus/**' \
           ':!tests/packaging/layers_fixture/**')
[ $check -eq 1 ] && [ $missing -eq 1 ] && { echo "add them with scripts/spdx.sh"; exit 1; }
exit 0
