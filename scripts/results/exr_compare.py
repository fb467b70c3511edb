#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Two of vplrender's EXR images compared, standard library only (exr_region_means.py's reader):
#   exr_compare.py A.exr B.exr [N]
# prints the image means (of R, G and B), A's mean over B's, relMSE = mean over pixels of
# (a - b)^2 / mean(b)^2 on the RGB mean, and the N pixels (default 5) with the largest squared
# difference with their share of it.
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_region_means import read_exr  # noqa: E402


def rgb_mean(path):
    w, h, img = read_exr(path)
    return w, h, [(img['R'][i] + img['G'][i] + img['B'][i]) / 3 for i in range(w * h)]


def main(argv):
    if len(argv) not in (2, 3):
        raise SystemExit('usage: exr_compare.py A.exr B.exr [N]')
    w, h, a = rgb_mean(argv[0])
    w2, h2, b = rgb_mean(argv[1])
    if (w, h) != (w2, h2):
        raise SystemExit(f'{argv[0]} is {w}x{h}, {argv[1]} is {w2}x{h2}')
    n = w * h
    ma, mb = sum(a) / n, sum(b) / n
    d = [(a[i] - b[i]) ** 2 for i in range(n)]
    total = sum(d)
    print(f'mean {ma:.6e} / {mb:.6e} = {ma / mb:.5f}; relMSE {total / n / mb ** 2:.3e}')
    for i in sorted(range(n), key=lambda k: -d[k])[:int(argv[2]) if len(argv) == 3 else 5]:
        print(f'  pixel ({i % w}, {i // w}): {a[i]:.4f} against {b[i]:.4f}, {100 * d[i] / total:.1f} % of the squared difference')


if __name__ == '__main__':
    main(sys.argv[1:])
