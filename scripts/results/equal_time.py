#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Equal-time tables from speed_vs_error runs (PREFIX.csv), standard library only.
#
#   equal_time.py [--budgets 16,64,256] [--target ris-mis] [--column relmse_exact_net] PREFIX...
#
# The budgets are the times `global` takes for the budget sample counts (the median over the runs
# given that hold global, at least one; all runs must be of one scene and size). At each, every method of every run is read off its
# (time, relMSE) points: interpolated log-log between measured points, extrapolated as 1/t beyond its
# last (or before its first) point (marked *). Times are total_ms (build + estimate) and relMSEs the
# column given, both means over seeds. Then the target method of each run against the best of every
# other method in every run ("best other"; a run with --dirs-per-sample R != 1 holds mis at that R):
# its relMSE and the ratio target / best other. Each run is timed on its own, so the machine's load
# during a run shifts that run's times: run them back to back on an otherwise idle machine.
import csv
import math
import statistics
import sys


def load(prefix):
    path = prefix if prefix.endswith('.csv') else prefix + '.csv'
    series = {}
    for r in csv.DictReader(open(path)):
        series.setdefault(r['method'], {}).setdefault(int(r['samples']), []).append(r)
    return series


def points(runs, column):
    return sorted((statistics.mean(float(r['total_ms']) for r in rs), statistics.mean(float(r[column]) for r in rs), n)
                  for n, rs in runs.items())


def at(pts, t):
    """relMSE at time t and whether it was extrapolated."""
    if t <= pts[0][0]:
        return pts[0][1] * pts[0][0] / t, t < pts[0][0]
    if t >= pts[-1][0]:
        return pts[-1][1] * pts[-1][0] / t, t > pts[-1][0]
    for (ta, ea, _), (tb, eb, _) in zip(pts, pts[1:]):
        if ta <= t <= tb:
            f = (math.log(t) - math.log(ta)) / (math.log(tb) - math.log(ta))
            if ea > 0 and eb > 0:
                return math.exp(math.log(ea) + f * (math.log(eb) - math.log(ea))), False
            return ea + f * (eb - ea), False
    raise AssertionError


def main(argv):
    budgets, target, column, prefixes = [16, 64, 256], 'ris-mis', 'relmse_exact_net', []
    i = 0
    while i < len(argv):
        if argv[i] == '--budgets':
            budgets = [int(x) for x in argv[i + 1].split(',')]; i += 2
        elif argv[i] == '--target':
            target = argv[i + 1]; i += 2
        elif argv[i] == '--column':
            column = argv[i + 1]; i += 2
        else:
            prefixes.append(argv[i]); i += 1
    if not prefixes:
        raise SystemExit(__doc__ if __doc__ else 'usage: equal_time.py [--budgets LIST] [--target M] PREFIX...')
    runs = {p: load(p) for p in prefixes}
    scenes = {(r['scene'], r['width'], r['height']) for s in runs.values() for rs in s.values() for rr in rs.values() for r in rr}
    if len(scenes) != 1:
        raise SystemExit(f'runs of different scenes or sizes: {sorted(scenes)}')
    if not any('global' in s for s in runs.values()):
        raise SystemExit('no run has a global series (its times are the budgets)')
    name = lambda p: p.rstrip('/').split('/')[-1].removesuffix('.csv')
    print(f'| budget (global at) | time ms | best other | run | {target} | {target} / best other |')
    print('|---|---:|---|---|---:|---:|')
    for b in budgets:
        times = []
        for p, s in runs.items():
            if 'global' not in s:
                continue
            g = [x for x in points(s['global'], column) if x[2] == b]
            if not g:
                raise SystemExit(f'{p}: global has no {b}-sample run')
            times.append(g[0][0])
        t = statistics.median(times)
        vals = {p: {m: at(points(rs, column), t) for m, rs in s.items()} for p, s in runs.items()}
        best = min(((v[0], f'{m} ({name(p)})', v[1]) for p, vs in vals.items() for m, v in vs.items() if m != target),
                   key=lambda x: x[0])
        for p, vs in vals.items():
            if target not in vs:
                continue
            e, ext = vs[target]
            print(f'| {b} | {t:.0f} | {best[1]} {best[0]:.3e}{"*" if best[2] else ""} | {name(p)} | '
                  f'{e:.3e}{"*" if ext else ""} | {e / best[0]:.2f} |')

if __name__ == '__main__':
    main(sys.argv[1:])
