#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# SIGTERM (and SIGINT) sent to a running vplrender: the temporaries of its outputs are removed, the
# previous run's files stay as they were, and the process dies of the signal.
#   sigterm_cleans_up.sh <vplrender> <work dir> <TERM|INT>
set -u
exe=$1 dir=$2 sig=$3
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir" || exit 1
printf 'old exr' > out.exr; printf 'old png' > out.png; printf 'old json' > out.json
# A CPU render of several seconds; the signal comes as soon as the temporaries exist.
"$exe" --backend cpu --method reference --size 256x256 --vpls 4096 --dprsm 16 --voxels 16 --progress never \
  --out out.exr > log.txt 2>&1 &
pid=$!
for _ in $(seq 1 600); do
  compgen -G '.*.tmp' > /dev/null && break
  kill -0 "$pid" 2> /dev/null || break
  sleep 0.05
done
if ! compgen -G '.*.tmp' > /dev/null; then
  echo "FAIL: no temporaries appeared while vplrender ran"; cat log.txt; kill "$pid" 2> /dev/null; exit 1
fi
kill -"$sig" "$pid"
wait "$pid"; rc=$?
want=$((128 + $(kill -l "$sig")))
status=0
[ "$rc" -eq "$want" ] || { echo "FAIL: exit status $rc, expected $want (killed by SIG$sig)"; status=1; }
left=$(compgen -G '.*.tmp')
[ -z "$left" ] || { echo "FAIL: temporaries left behind: $left"; status=1; }
[ "$(cat out.exr)" = "old exr" ] && [ "$(cat out.png)" = "old png" ] && [ "$(cat out.json)" = "old json" ] ||
  { echo "FAIL: the previous outputs changed"; status=1; }
[ $status -eq 0 ] && echo "OK: SIG$sig removed the temporaries and kept the previous outputs"
cat log.txt
exit $status
