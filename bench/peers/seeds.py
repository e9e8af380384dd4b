#!/usr/bin/env python3
"""Tabulate bench/peers/seeds.sh: the pour bed's physics, LIGGGHTS 3.8 against Sable, over seeds.

Usage: seeds.py ROOT [ROOT ...] [--out FILE]

Each ROOT is one seed's run folder in compare.sh's layout (meta.txt, runs/r1_cC_CODE/); the runs
are read by compare.py's gather(), so both scripts measure the bed the same way (see compare.py:
bulk region, solid fraction, coordination, floor / weight at the last step of phase (b)).

For each quantity it prints every seed's beds, then:
  - each code's mean and standard deviation over seeds (LIGGGHTS on 1 and on 2 ranks apart);
  - bed against bed, as compare.sh's single-bed rows judge them: Sable - LIGGGHTS relative to
    LIGGGHTS, for each rank count, and LIGGGHTS 2 ranks - LIGGGHTS 1 rank, the peer against
    itself; how many of the seeds exceed the issue's bound, and the largest difference;
  - the mean of the paired difference d = Sable - (LIGGGHTS 1 rank + 2 ranks) / 2 over seeds with
    its standard error (sd / sqrt(n)): a systematic difference between the codes shows as a mean
    that is several standard errors from zero; beds that are draws from one distribution give a
    mean within about two.
"""
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402  (same folder)

QUANTITIES = (("solid_fraction", "bulk solid fraction", "{:.4f}"),
              ("coordination", "bulk coordination", "{:.3f}"),
              ("floor_force", "floor force / weight", "{:.4f}"))


def beds(root):
    """{(code, cores): phys} of one seed's runs; raises on a failed run."""
    out = {}
    for r in compare.gather(root):
        if "error" in r:
            raise ValueError(f"{r['dir']}: {r['error']}")
        out[(r["code"], r["cores"])] = r["phys"]
    return out


def sd(v):
    return statistics.stdev(v) if len(v) > 1 else float("nan")


def rel(a, b):
    return (a - b) / abs(b)


def summary(w, seeds, data, q, label, f):
    tol = compare.TARGETS[q]
    ranks = sorted({c for d in data for (code, c) in d if code == "liggghts"})
    w(f"### {label} (bound on one bed: +-{tol * 100:.0f} %)")
    w("")
    head = "| seed | " + " | ".join(f"LIGGGHTS {c} rank(s)" for c in ranks) + " | Sable | " + \
        " | ".join(f"Sable vs {c} rank(s)" for c in ranks) + \
        (" | LIGGGHTS 2 vs 1 rank |" if ranks == [1, 2] else " |")
    w(head)
    w("|" + "---|" * (head.count("|") - 1))
    pairs = {f"Sable vs LIGGGHTS {c} rank(s)": [] for c in ranks}
    if ranks == [1, 2]:
        pairs["LIGGGHTS 2 vs 1 rank (the peer against itself)"] = []
    paired = []
    for s, d in zip(seeds, data):
        lv = [d[("liggghts", c)][q] for c in ranks]
        sv = d[("sable", 1)][q]
        diffs = [rel(sv, x) for x in lv]
        for c, x in zip(ranks, diffs):
            pairs[f"Sable vs LIGGGHTS {c} rank(s)"].append(x)
        row = f"| {s} | " + " | ".join(f.format(x) for x in lv) + f" | {f.format(sv)} | " + \
            " | ".join(f"{x * 100:+.2f} %" for x in diffs)
        if ranks == [1, 2]:
            self_diff = rel(lv[1], lv[0])
            pairs["LIGGGHTS 2 vs 1 rank (the peer against itself)"].append(self_diff)
            row += f" | {self_diff * 100:+.2f} %"
        w(row + " |")
        paired.append(sv - statistics.fmean(lv))
    w("")
    n = len(seeds)
    for c in ranks:
        v = [d[("liggghts", c)][q] for d in data]
        w(f"- LIGGGHTS {c} rank(s): mean {f.format(statistics.fmean(v))}, sd {sd(v):.4f}")
    v = [d[("sable", 1)][q] for d in data]
    w(f"- Sable: mean {f.format(statistics.fmean(v))}, sd {sd(v):.4f}")
    for name, x in pairs.items():
        out = sum(1 for y in x if abs(y) > tol)
        w(f"- {name}: {out} of {n} beds beyond +-{tol * 100:.0f} %, largest "
          f"{max(abs(y) for y in x) * 100:.2f} %, rms {math.sqrt(statistics.fmean([y * y for y in x])) * 100:.2f} %")
    lmean = statistics.fmean([statistics.fmean([d[("liggghts", c)][q] for c in ranks]) for d in data])
    m, e = statistics.fmean(paired), sd(paired) / math.sqrt(n) if n > 1 else float("nan")
    w(f"- paired difference Sable - LIGGGHTS (mean of its ranks): {m / lmean * 100:+.2f} % "
      f"+- {e / lmean * 100:.2f} % (standard error), {abs(m) / e if e > 0 else float('nan'):.1f} "
      "standard errors from zero")
    w("")


def main(argv):
    out_path = None
    roots = []
    i = 0
    while i < len(argv):
        if argv[i] == "--out":
            if i + 1 >= len(argv):
                sys.exit("seeds.py: --out needs a file name")
            out_path = argv[i + 1]
            i += 2
        else:
            roots.append(argv[i])
            i += 1
    if not roots:
        sys.exit(__doc__)
    seeds, data, failed = [], [], []
    for root in roots:
        meta = compare.read_meta(root)
        try:
            d = beds(root)
            missing = [k for k in (("sable", 1), ("liggghts", 1)) if k not in d]
            if missing:
                raise ValueError(f"{root}: no run of {missing}")
        except (OSError, ValueError) as e:
            failed.append(str(e))
            continue
        seeds.append(meta.get("seed", os.path.basename(os.path.dirname(root))))
        data.append(d)
    lines = []
    w = lines.append
    w("# The pour bed over seeds: LIGGGHTS 3.8 against Sable")
    w("")
    meta = compare.read_meta(roots[0])
    w(f"- {len(seeds)} seeds; E = {meta.get('E', '?')} Pa, dt = {meta.get('dt', '?')} s, "
      f"{meta.get('nsettle', '?')} + {meta.get('nstatic', '?')} steps; Sable "
      f"{meta.get('sable', '?')}, {meta.get('liggghts', '?')}; first seed started "
      f"{meta.get('date', '?')}")
    w("- relative differences are (x - reference) / reference, as in compare.sh's table")
    if failed:
        w("- FAILED (left out): " + "; ".join(failed))
    w("")
    if data:
        for q, label, f in QUANTITIES:
            summary(w, seeds, data, q, label, f)
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    if out_path:
        with open(out_path, "w") as fh:
            fh.write(text)
    return 1 if failed or not data else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
