#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# docs/results/clamp_compensation.md, "Directions per pixel": how many directions of the clamp's
# compensation (vplrender --clamp-compensation-dirs) minimise the error at equal time.
# Run by scripts/results/clamp_compensation.sh with PART=dirs (its settings: BUILD, OUT, CACHE,
# SIZE, REF_DIRS, SCENES_LIST; here also RULES, DIRS_SAMPLES, DIRS_SEEDS, METHODS, TIME_REPEATS).
# Per scene, CPU backend, exact visibility, the frame of clamp_compensation.sh:
#  1. speed_vs_error with --clamp-compensation off at DIRS_SAMPLES and 4x the largest (for the
#     interpolation), and with --clamp-compensation on once per rule (RULES: auto 1:4 1:16 1:64 1):
#     relMSE against (c) per (method, samples, seed); the clamped and compensated runs of a seed
#     share every VPL sample, so their difference is the term's alone;
#  2. the cost: vplrender's JSON `clamp_compensation_cpu_ms` (the compensation pass's CPU time, all
#     threads) over `estimate_cpu_ms` (the clamped estimate's), per (method, samples, rule), median
#     of TIME_REPEATS runs (seed 1). CPU times, not the stages' wall times: on a loaded 2-core
#     machine a pass's wall time depends on what else runs, its CPU time hardly;
#  3. equal time: relMSE of the compensated run at n samples against the clamped series at
#     n (1 + cost) samples, interpolated in log(samples)-log(relMSE) (as "Cost and equal time").
import csv
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

sve, vplrender, out, cache = sys.argv[1:5]
scene_args = {s.split("=", 1)[0]: s.split("=", 1)[1].split("\x1f") for s in sys.argv[5:]}
size = os.environ.get("SIZE", "48x48")
ref_dirs = os.environ.get("REF_DIRS", "1024")
rules = os.environ.get("RULES", "auto 1:4 1:16 1:64 1").split()
samples = [int(x) for x in os.environ.get("DIRS_SAMPLES", "16,64,256").split(",")]
seeds = os.environ.get("DIRS_SEEDS", "1,2,3,4")
methods = os.environ.get("METHODS", "global,local,gbg")
time_repeats = int(os.environ.get("TIME_REPEATS", "3"))
frame = ["--backend", "cpu", "--visibility", "exact", "--size", size, "--dprsm", "128", "--voxels", "64"]
common = frame + ["--references", "exact", "--ref-exact-dirs", ref_dirs, "--methods", methods, "--seeds", seeds,
                  "--cache-dir", cache]


def sweep(sa, prefix, extra, sample_list):
    if not (os.environ.get("REUSE") and os.path.exists(prefix + ".csv")):  # REUSE=1: the CSVs of an earlier run
        subprocess.run([sve, *sa, *common, "--samples", ",".join(map(str, sample_list)), *extra, "--out", prefix],
                       check=True, stdout=subprocess.DEVNULL)
    rows = {}
    with open(prefix + ".csv") as f:
        for r in csv.DictReader(f):
            rows.setdefault((r["method"], int(r["samples"])), []).append(r)
    return rows


def cpu_cost(sa, tmp, m, n, rule):
    """Median over TIME_REPEATS of the term's CPU ms / the clamped estimate's, and the directions."""
    r = []
    for _ in range(time_repeats):
        o = os.path.join(tmp, "t.exr")
        subprocess.run([vplrender, *sa, *frame, "--method", m, "--vpls", str(n), "--clamp-compensation-dirs", rule,
                        "--progress", "never", "--out", o], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        e = json.load(open(os.path.join(tmp, "t.json")))["pipeline"]["estimator"]
        r.append((e["clamp_compensation_cpu_ms"] / e["estimate_cpu_ms"], e["clamp_compensation_cpu_ms"],
                  e["estimate_cpu_ms"], e["clamp_compensation_dirs"]))
    r.sort()
    return r[(len(r) - 1) // 2]


def loglog(points, t):
    """relMSE at t samples from (samples, relMSE) points, linear in log-log between neighbours."""
    pts = sorted(points)
    for (a, ra), (b, rb) in zip(pts, pts[1:]):
        if a <= t <= b:
            return math.exp(math.log(ra) + (math.log(t) - math.log(a)) / (math.log(b) - math.log(a)) *
                            (math.log(rb) - math.log(ra)))
    return None


def rel(r):
    """relMSE against (c): net of (c)'s own noise where speed_vs_error measured it (--ref-noise)."""
    return float(r["relmse_exact_net"] if r.get("relmse_exact_net") else r["relmse_exact"])


def mean_rel(rows):
    return statistics.mean(rel(r) for r in rows)


for scene, sa in scene_args.items():
    tmp = tempfile.mkdtemp()
    base = os.path.join(out, f"clamp_dirs_{scene}")
    off = sweep(sa, base + "_off", ["--clamp-compensation", "off"], samples + [4 * samples[-1]])
    on = {rule: sweep(sa, base + "_" + rule.replace(":", "-"), ["--clamp-compensation", "on",
                                                                "--clamp-compensation-dirs", rule], samples)
          for rule in rules}
    ms = sorted({m for m, _ in off})
    costs = {(m, n, rule): cpu_cost(sa, tmp, m, n, rule) for m in ms for n in samples for rule in rules}
    lines = [f"### {scene}", "", f"Directions per pixel and CPU ms of the term / of the clamped estimate (global; "
             f"median of {time_repeats} runs):", "",
             "| rule | " + " | ".join(f"{n} samples" for n in samples) + " |", "|---|" + "---:|" * len(samples)]
    for rule in rules:
        lines.append(f"| {rule} | " + " | ".join(
            f"{costs['global', n, rule][3]} dirs: {costs['global', n, rule][1]:.1f} / {costs['global', n, rule][2]:.0f}"
            for n in samples) + " |")
    lines += ["", "relMSE against (c) (net of (c)'s own noise when the CSVs have it: speed_vs_error --ref-noise), "
              "mean over the seeds; in brackets (compensated - clamped) / clamped, paired "
              "per seed (the term's variance less the bias it removes); cost = the term's CPU time / the clamped "
              "estimate's (2. above); ratio = compensated relMSE / clamped relMSE at samples x (1 + cost) (< 1: the compensation pays "
              "at equal time):", "",
              "| method | samples | clamped | " +
              " | ".join(f"{r}: relMSE (delta) | cost | ratio" for r in rules) + " |",
              "|---|---:|---:|" + "---:|---:|---:|" * len(rules)]
    for m in ms:
        curve = [(n, mean_rel(off[m, n])) for (mm, n) in off if mm == m]
        for n in samples:
            r_off = mean_rel(off[m, n])
            cells = []
            for rule in rules:
                rows = on[rule][m, n]
                r_on = mean_rel(rows)
                by_seed = {r["seed"]: rel(r) for r in off[m, n]}
                delta = statistics.mean(rel(r) / by_seed[r["seed"]] - 1 for r in rows)
                cost = costs[m, n, rule][0]
                eq = loglog(curve, n * (1 + cost))
                cells.append(f"{r_on:.4e} ({100 * delta:+.2f} %) | {100 * cost:.1f} % | " +
                             (f"{r_on / eq:.3f}" if eq else "-"))
            lines.append(f"| {m} | {n} | {r_off:.4e} | " + " | ".join(cells) + " |")
    with open(base + "_summary.md", "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
