#!/usr/bin/env python3
"""Tabulate bench/peers/roundoff.sh: trajectories of one pour bed, LIGGGHTS 3.8 and Sable.

Usage: roundoff.py ROOT [ROOT ...] [--meta FILE] [--out FILE]

Each ROOT is one trajectory's run folder in compare.sh's layout (runs/r1_cC_CODE/), named
PEERS_OUT/NAME/soft; the runs are read by compare.py's gather(), so the beds are measured as
compare.sh measures them (bulk region, solid fraction, coordination, floor / weight at the last
step of phase (b)).

For each quantity: every trajectory's value, then for each code its mean, standard deviation and
range over its trajectories, and:
  - the difference of the means, Sable - LIGGGHTS, relative to LIGGGHTS' mean, with its standard
    error sqrt(sd_L^2 / n_L + sd_S^2 / n_S): a systematic difference between the codes shows as
    several standard errors;
  - bed against bed, as compare.sh's rows judge one bed against another: of the pairs of
    LIGGGHTS trajectories, and of the (Sable, LIGGGHTS) pairs, how many differ by more than the
    issue's bound. The relative difference of a pair is |a - b| / ((a + b) / 2) (symmetric;
    within 0.05 % of compare.sh's (Sable - LIGGGHTS) / LIGGGHTS at these values).
"""
import itertools
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402  (same folder)

QUANTITIES = (("floor_force", "floor force / weight", "{:.4f}"),
              ("solid_fraction", "bulk solid fraction", "{:.4f}"),
              ("coordination", "bulk coordination", "{:.3f}"))


def sd(v):
    return statistics.stdev(v) if len(v) > 1 else float("nan")


def rel_pair(a, b):
    return abs(a - b) / (0.5 * (a + b))


def summary(w, beds, q, label, f):
    tol = compare.TARGETS[q]
    w(f"### {label} (bound on one bed against another: +-{tol * 100:.0f} %)")
    w("")
    w("| trajectory | code | cores | value |")
    w("|---|---|---|---|")
    for b in beds:
        w(f"| {b['name']} | {b['code']} | {b['cores']} | {f.format(b['phys'][q])} |")
    w("")
    values = {c: [b["phys"][q] for b in beds if b["code"] == c] for c in ("liggghts", "sable")}
    for code, v in values.items():
        if v:
            w(f"- {code}: {len(v)} trajectories, mean {f.format(statistics.fmean(v))}, sd "
              f"{sd(v):.4f}, range {f.format(min(v))} - {f.format(max(v))} "
              f"({(max(v) - min(v)) / statistics.fmean(v) * 100:.2f} % of the mean)")
    lv, sv = values["liggghts"], values["sable"]
    if len(lv) > 1 and len(sv) > 1:
        lm, sm = statistics.fmean(lv), statistics.fmean(sv)
        err = math.sqrt(sd(lv) ** 2 / len(lv) + sd(sv) ** 2 / len(sv))
        w(f"- means, Sable - LIGGGHTS: {(sm - lm) / lm * 100:+.2f} % +- {err / lm * 100:.2f} % "
          f"(standard error), {abs(sm - lm) / err if err > 0 else float('nan'):.1f} standard "
          "errors from zero")
    ll = [rel_pair(a, b) for a, b in itertools.combinations(lv, 2)]
    sl = [rel_pair(a, b) for a in sv for b in lv]
    for name, x in (("LIGGGHTS against LIGGGHTS", ll), ("Sable against LIGGGHTS", sl)):
        if x:
            out = sum(1 for y in x if y > tol)
            w(f"- {name}: {out} of {len(x)} pairs of beds differ by more than "
              f"{tol * 100:.0f} %, largest {max(x) * 100:.2f} %")
    w("")


def main(argv):
    out_path = meta_path = None
    roots = []
    i = 0
    while i < len(argv):
        if argv[i] in ("--out", "--meta"):
            if i + 1 >= len(argv):
                sys.exit(f"roundoff.py: {argv[i]} needs a file name")
            if argv[i] == "--out":
                out_path = argv[i + 1]
            else:
                meta_path = argv[i + 1]
            i += 2
        else:
            roots.append(argv[i])
            i += 1
    if not roots:
        sys.exit(__doc__)
    beds, failed = [], []
    for root in roots:
        name = os.path.basename(os.path.dirname(os.path.abspath(root)))
        try:
            runs = compare.gather(root)
            if len(runs) != 1:
                raise ValueError(f"{root}: {len(runs)} runs, expected one")
            if "error" in runs[0]:
                raise ValueError(runs[0]["error"])
            r = runs[0]
            beds.append({"name": name, "code": r["code"], "cores": r["cores"], "phys": r["phys"],
                         "hash": r.get("hash", "")})
        except (OSError, ValueError) as e:
            failed.append(f"{name}: {e}")
    meta = {}
    if meta_path:
        for line in open(meta_path):
            if "=" in line:
                k, v = line.rstrip("\n").split("=", 1)
                meta[k] = v
    lines = []
    w = lines.append
    w(f"# One pour bed (seed {meta.get('seed', '?')}), many trajectories: LIGGGHTS 3.8 and Sable")
    w("")
    w(f"- E = {meta.get('E', '?')} Pa, dt = {meta.get('dt', '?')} s, {meta.get('nsettle', '?')} + "
      f"{meta.get('nstatic', '?')} steps; Sable {meta.get('sable', '?')}; "
      f"{meta.get('liggghts', '?')}; started {meta.get('date', '?')}")
    w("- each trajectory changes only the order of floating-point sums (bench/peers/roundoff.sh)")
    hashes = [b["hash"] for b in beds if b["code"] == "sable"]
    if hashes:
        w(f"- Sable's state hashes: {', '.join(hashes)} ({len(set(hashes))} different)")
    if failed:
        w("- FAILED (left out): " + "; ".join(failed))
    w("")
    for q, label, f in QUANTITIES:
        if beds:
            summary(w, beds, q, label, f)
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    if out_path:
        with open(out_path, "w") as fh:
            fh.write(text)
    return 1 if failed or not beds else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
