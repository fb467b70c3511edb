#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# The clamp compensation at equal time, paired (results/clamp_compensation.md, "Equal time, paired").
#
#   clamp_compensation_paired.py CC_PREFIX CL_PREFIX
#
# CC_PREFIX: a speed_vs_error sweep with --clamp-compensation off,on --references vplsum,exact
# (reference (a) = the compensated VPL sum); CL_PREFIX: the same sweep with --clamp-compensation off
# (reference (a) = the clamped VPL sum). Both with --ref-noise on (the default) and 2 or more seeds.
#
# The compensation draws from a stream of its own, so a compensated run has the clamped run's VPL
# samples bit for bit: per seed, relMSE(off) - relMSE(on) cancels the VPL noise that dominates
# either, and its mean over the seeds, over the clamped mean relMSE, is the gain g at equal samples
# to a fraction of a percent.
# The cost c is the compensation's own stage time ("estimate: clamp compensation") over the
# clamped run's frame (build + estimate), not the difference of two noisy frame times. With the
# clamped series' local slope k (relMSE ~ n^-k), the equal-time ratio is (1 - g) (1 + c)^k
# (< 1: the compensation pays). What the compensation can gain at most is the squared bias it
# removes: dB / relMSE(n), dB = B(clamped sum) - B(compensated sum), B the VPL sum's relMSE against
# (c) net of (c)'s noise (the markdown headers); the compensated sum's own noise (256 directions)
# counts in its B, so dB is low by that. A hard upper bound on any compensation's gain is
# B(clamped) / relMSE(n): it cannot remove more than the whole bias. A term that costs more of the
# frame than it can gain cannot pay at n samples.
# Standard library only.
import csv
import math
import re
import statistics as st
import sys


def header(prefix):
    with open(prefix + '.md') as f:
        return f.readline()


def number(pattern, text, what):
    m = re.search(pattern, text)
    if not m:
        raise SystemExit(f'{what}: not found in the markdown header (speed_vs_error too old, or a reference skipped)')
    return float(m.group(1).rstrip('.'))


def stage_ms(row, name):
    for kv in row['stages'].split('|'):
        k, _, v = kv.rpartition('=')
        if k == name:
            return float(v)
    return 0.0


def main():
    if len(sys.argv) != 3:
        raise SystemExit('usage: clamp_compensation_paired.py CC_PREFIX CL_PREFIX')
    cc, cl = sys.argv[1], sys.argv[2]
    hcc, hcl = header(cc), header(cl)
    net = r'VPL sum vs exact [0-9.e+-]+ \(relMSE net of exact\'s noise (-?[0-9.e+-]+)\)'
    b_clamped = number(net, hcl, f'{cl}.md: clamped VPL sum vs exact, net')
    b_comp = number(net, hcc, f'{cc}.md: compensated VPL sum vs exact, net')
    ex_mean = number(r'Image means: VPL sum [0-9.e+-]+, gathering [-0-9.e+]+, exact ([0-9.e+-]+)', hcc, 'exact mean')
    ex_band = number(r'Junction band .*?means: VPL sum [0-9.e+-]+, gathering [-0-9.e+]+, exact ([0-9.e+-]+)', hcc,
                     'exact band mean')
    a_mean = {p: number(r'Image means: VPL sum ([0-9.e+-]+),', h, p) for p, h in ((cc, hcc), (cl, hcl))}
    a_band = {p: number(r'Junction band .*?means: VPL sum ([0-9.e+-]+),', h, p) for p, h in ((cc, hcc), (cl, hcl))}
    print(f'VPL sum against (c): clamped image {100 * (a_mean[cl] / ex_mean - 1):+.2f} %, band '
          f'{100 * (a_band[cl] / ex_band - 1):+.2f} %, relMSE net {b_clamped:.3e}; compensated image '
          f'{100 * (a_mean[cc] / ex_mean - 1):+.2f} %, band {100 * (a_band[cc] / ex_band - 1):+.2f} %, '
          f'relMSE net {b_comp:.3e}')
    with open(cc + '.csv') as f:
        rows = list(csv.DictReader(f))
    print()
    print('| method | samples | relMSE net, clamped | gain at equal samples (se) | dB / relMSE | B(clamped) / relMSE | '
          'compensation / frame | equal-time ratio |')
    print('|---|---:|---:|---:|---:|---:|---:|---:|')
    for meth in sorted({r['method'] for r in rows if r['clamp_compensation'] == 'on'}):
        ns = sorted({int(r['samples']) for r in rows if r['method'] == meth})

        def runs(comp, n):
            return sorted((r for r in rows if r['method'] == meth and r['clamp_compensation'] == comp
                           and int(r['samples']) == n), key=lambda r: int(r['seed']))
        rel = {n: st.mean(float(r['relmse_exact_net']) for r in runs('off', n)) for n in ns}
        for i, n in enumerate(ns):
            off, on = runs('off', n), runs('on', n)
            if len(off) != len(on) or len(off) < 2:
                raise SystemExit(f'{meth} at {n}: needs the same 2 or more seeds with and without the compensation')
            # The gain on the seeds' mean relMSE (not the mean of per-seed ratios, which weighs the
            # seeds with little error up): the paired differences carry its standard error.
            diffs = [float(a['relmse_exact_net']) - float(b['relmse_exact_net']) for a, b in zip(off, on)]
            g = st.mean(diffs) / rel[n]
            se = st.stdev(diffs) / math.sqrt(len(diffs)) / rel[n]
            c = st.mean(stage_ms(r, 'estimate: clamp compensation (cpu)') + stage_ms(r, 'estimate: clamp compensation (gpu)')
                        for r in on) / st.mean(float(r['total_ms']) for r in off)
            j0, j1 = (i - 1, i) if i > 0 else (0, 1)
            k = -(math.log(rel[ns[j1]]) - math.log(rel[ns[j0]])) / (math.log(ns[j1]) - math.log(ns[j0])) \
                if len(ns) > 1 else 1.0
            print(f'| {meth} | {n} | {rel[n]:.3e} | {100 * g:+.2f} % ({100 * se:.2f}) | {100 * (b_clamped - b_comp) / rel[n]:.2f} % | '
                  f'{100 * b_clamped / rel[n]:.2f} % | '
                  f'{100 * c:.2f} % | {(1 - g) * (1 + c) ** k:.4f} |')


if __name__ == '__main__':
    main()
