#!/bin/bash
# SPDX-License-Identifier: MIT
# Table 1 analogue: time of global, local, gbg and mis at 800 VPLs per pixel with the paper's
# parameters (--paper: 512x512, DPRSM 2x512x512, 128^3 voxels, 4 regions), each run REPEATS times
# (median and min), with its error against converged gathering (the exhaustive VPL sum at 2x512^2
# VPLs per pixel would take hours here). mis at 800 means 800 VPLs and 800 directions.
source "$(dirname "$0")/common.sh"
for s in ${SCENES_LIST:-cornell open sponza}; do
  mapfile -t sa < <(scene_args "$s")
  "$SVE" "${sa[@]}" --paper --backend ${BACKEND:-gpu} --methods global,local,gbg,mis --samples 800 \
    --references gather --ref-dirs ${REF_DIRS:-1024} --repeats ${REPEATS:-3} --cache-dir "$CACHE" \
    --out "$OUT/table1_${s}_${BACKEND:-gpu}"
done
