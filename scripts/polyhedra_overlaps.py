#!/usr/bin/python3
"""The overlaps of contact dynamics with polyhedral grains, over seeds.

Runs tests/data/polyhedra_fall.toml (48 polyhedra falling into a box) for seeds 1..N, with
the step divided by --divide (the stages' steps multiplied by it) and cd.overlap_recovery set
to --beta, and prints the median over the seeds of series.csv's max_overlap_over_radius: its
largest in the run (the impacts) and its last (the settled heap), with the end kinetic
energy. docs/contact-dynamics.md ("Overlaps") records what it gave.

usage: scripts/polyhedra_overlaps.py BUILD/bin/sable [--seeds 8] [--divide 1] [--beta 0]
"""
import argparse
import csv
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent


def scenario(seed, divide, beta):
    text = (ROOT / "tests/data/polyhedra_fall.toml").read_text()
    dt = float(re.search(r"^dt = (\S+)", text, re.M).group(1))
    text = re.sub(r"^seed = \d+", f"seed = {seed}", text, flags=re.M)
    text = re.sub(r"^dt = \S+", f"dt = {dt / divide!r}", text, flags=re.M)
    text = re.sub(r"^steps = (\d+)", lambda m: f"steps = {int(m.group(1)) * divide}", text,
                  flags=re.M)
    text = re.sub(r"^overlap_recovery = .*\n", "", text, flags=re.M)
    text = text.replace("[cd]\n", f"[cd]\noverlap_recovery = {beta!r}\n")
    return re.sub(r"^csv_interval = \d+", "csv_interval = 1", text, flags=re.M)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sable")
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--divide", type=int, default=1)
    ap.add_argument("--beta", type=float, default=0.0)
    a = ap.parse_args()
    largest, last, energy = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, a.seeds + 1):
            path = pathlib.Path(tmp) / f"s{seed}.toml"
            path.write_text(scenario(seed, a.divide, a.beta))
            out = pathlib.Path(tmp) / f"out{seed}"
            run = subprocess.run([a.sable, "run", str(path), "--out", str(out)],
                                 capture_output=True, text=True)
            if run.returncode != 0:
                sys.exit(f"seed {seed}: sable exited {run.returncode}: {run.stderr[-2000:]}")
            with open(out / "series.csv") as f:
                rows = list(csv.DictReader(f))
            o = [float(r["max_overlap_over_radius"]) for r in rows]
            largest.append(max(o))
            last.append(o[-1])
            energy.append(float(rows[-1]["kinetic_energy_J"]))
    print(f"seeds {a.seeds}, dt / {a.divide}, overlap_recovery {a.beta}: median largest "
          f"{statistics.median(largest):.3g}, at the end {statistics.median(last):.3g}, "
          f"end kinetic energy {statistics.median(energy):.3g} J")


if __name__ == "__main__":
    main()
