# SPDX-License-Identifier: MIT
# Shared settings of the results scripts (sourced). BUILD: a build directory with the examples
# (default build/release, made by `cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release
# -DVPLKIT_BUILD_EXAMPLES=ON`); SCENES: the shared scenes folder (default ../shared/scenes);
# OUT: where the CSV/MD/SVG land (default docs/results); CACHE: the reference cache.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD=${BUILD:-$ROOT/build/release}
SCENES=${SCENES:-$ROOT/../shared/scenes}
OUT=${OUT:-$ROOT/docs/results}
CACHE=${CACHE:-$ROOT/build/results_cache}
SVE=$BUILD/examples/speed_vs_error/speed_vs_error
VPLRENDER=$BUILD/examples/vplrender/vplrender
mkdir -p "$OUT" "$CACHE"
for exe in "$SVE" "$VPLRENDER"; do
  [[ -x $exe ]] || { echo "missing $exe: build the examples first (see the header of $0)" >&2; exit 1; }
done
# The Dabrovic Sponza, its light and camera as documented in docs/results.md: the light on the
# atrium's centre line at 3/4 of its height (the automatic intensity, 432.5 W/sr), the camera at the
# west end under the arch, looking east along the nave.
SPONZA_OBJ=$SCENES/sponza/sponza.obj
SPONZA=(--scene "$SPONZA_OBJ" --camera -15,2.5,0,5,4.5,0,0,1,0,60 --light 0,11.5,0)
# scene_args NAME: the flags that select a scene by short name (cornell, open, sponza).
scene_args() {
  case $1 in
    sponza) [[ -f $SPONZA_OBJ ]] || { echo "no $SPONZA_OBJ (set SCENES)" >&2; exit 1; }
            printf '%s\n' "${SPONZA[@]}" ;;
    *) printf '%s\n' --scene "$1" ;;
  esac
}
