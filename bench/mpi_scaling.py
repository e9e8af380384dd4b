"""The MPI scaling model (docs/BENCHMARKS.md, "MPI"): its inputs measured here, on the settled
pour bed, with 2 to 8 processes, oversubscribed; its predictions for 300,000 and 10,000,000
grains on 8 to 1,024 processes.

Usage: /usr/bin/python3 bench/mpi_scaling.py SNAPSHOT [STEPS]
  SNAPSHOT: examples/pour.toml's end_of_stage_1.h5 (the settled bed; `sable run
  examples/pour.toml` writes it in out/pour/snapshots/). Runs tests' sable_mpi_dem_check on
  it (its cuts by grain count) for STEPS steps (default 200) of the dense stage on 2, 4 and 8
  processes; reads each process's box, owned grains, ghosts, and the bytes and messages it
  sent a step and a list build.

The model: a process's ghosts are the grains within delta = 2 R_max + skin outside its box's
faces that are not the domain's, so ghosts = sigma * (interior face area), sigma (ghosts per
m^2 of interior face) measured with 2 processes and checked against 4 and 8. A ghost costs
b bytes a step (its position, velocity, spin and orientation: measured). At scale the boxes
are cubes of n_own grains with every face interior: ghosts = (sigma / delta) * ((a + 2 delta)^3
- a^3), a = (n_own delta / sigma)^(1/3), and 26 neighbours. A step then costs
  compute: (n_own + ghosts / 2) * t_gs   (a pair with a ghost is computed on both sides)
  ghost exchange: 26 messages * alpha + ghosts * b / beta   (point to point, neighbours only)
  list builds: 4 MPI_Alltoall(v) over every process, 4 * P * alpha_a2a, once every 385 steps
               (the settled bed's 13 builds in 5,000 steps)
  3 reductions: 2 log2(P) * (alpha + m / beta) each (recursive doubling), m = 16, 24 and
                the walls' exact totals 36 * 73 * 8 bytes
with alpha = 2 us, beta = 12.5 GB/s (a 100 Gb/s network), alpha_a2a = 0.2 us per process
(a zero-length slot of an all-to-all), t_gs the measured cost of a grain-step on one core.
Efficiency = N / P * t_gs / (step time). Last, the full-scale rotating-cylinder study
(examples/rotating-cylinder/full.toml: 292,500 grains of the same size, 11.4 M steps) on 32 and
256 processes, at T_GS_CYLINDER a grain-step (its settled bed's cost).
"""
import math
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHECK = os.path.join(ROOT, "build/release/tests/sable_mpi_dem_check")
SCENARIO = os.path.join(ROOT, "examples/pour.toml")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1")
LINE = re.compile(r"process (\d+): (\d+) grains owned, (\d+) ghosts; a step: (\d+) bytes in "
                  r"([\d.]+) messages; a list build: (\d+) bytes in ([\d.]+) messages "
                  r"\((\d+) builds\); box (.*) m")
ALPHA, BETA, ALPHA_A2A = 2e-6, 12.5e9, 0.2e-6
STEPS_PER_BUILD = 385
DELTA = 2 * 0.75e-3 + 0.5e-3  # the pour bed's ghost reach: 2 R_max + skin (m)
DOMAIN = ((0.0, 0.030), (0.0, 0.030), (0.0, 0.110))


def measure(np_, snapshot, steps):
    cmd = ["mpirun", "-np", str(np_), "--oversubscribe", CHECK, SCENARIO, str(steps), "1.0",
           "1", snapshot]
    out = subprocess.run(cmd, env=ENV, capture_output=True, text=True, timeout=1200).stdout
    rows = []
    for m in LINE.finditer(out):
        box = [tuple(float(v) for v in side.split("..")) for side in m.group(9).split(" x ")]
        rows.append(dict(rank=int(m.group(1)), owned=int(m.group(2)), ghosts=int(m.group(3)),
                         step_bytes=float(m.group(4)), step_msgs=float(m.group(5)),
                         build_bytes=float(m.group(6)), box=box))
    if len(rows) != np_ or "the same" not in out:
        sys.exit(f"{' '.join(cmd)}: unexpected output\n{out}")
    return sorted(rows, key=lambda r: r["rank"])


def interior_area(box):
    """The area of the box's faces that are not the domain's (where its ghosts come from)."""
    area = 0.0
    for d in range(3):
        side = math.prod(box[e][1] - box[e][0] for e in range(3) if e != d)
        area += side * ((box[d][0] > DOMAIN[d][0] + 1e-12) + (box[d][1] < DOMAIN[d][1] - 1e-12))
    return area


def step_time(n, p, sigma, bytes_per_ghost, t_gs):
    n_own = n / p
    a = (n_own * DELTA / sigma) ** (1 / 3)
    ghosts = sigma / DELTA * ((a + 2 * DELTA) ** 3 - a ** 3)
    compute = (n_own + ghosts / 2) * t_gs
    exchange = 26 * ALPHA + ghosts * bytes_per_ghost / BETA + 4 * p * ALPHA_A2A / STEPS_PER_BUILD
    rounds = 2 * math.log2(p)
    reduce = sum(rounds * (ALPHA + m / BETA) for m in (16, 24, 36 * 73 * 8))
    return ghosts, compute, exchange + reduce


def main():
    snapshot = sys.argv[1]
    steps = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    runs = {p: measure(p, snapshot, steps) for p in (2, 4, 8)}
    sigma = sum(r["ghosts"] for r in runs[2]) / sum(interior_area(r["box"]) for r in runs[2])
    per_ghost = [r["step_bytes"] / r["ghosts"] for p in runs for r in runs[p] if r["ghosts"]]
    bytes_per_ghost = sum(per_ghost) / len(per_ghost)
    print(f"measured: sigma = {sigma:.4g} ghosts per m^2 of interior face (2 processes), "
          f"{bytes_per_ghost:.1f} bytes per ghost a step")
    print("| processes | process | owned | ghosts | predicted ghosts | bytes a step | messages "
          "a step | bytes a list build |")
    print("|---|---|---|---|---|---|---|---|")
    for p, rows in runs.items():
        for r in rows:
            print(f"| {p} | {r['rank']} | {r['owned']} | {r['ghosts']} | "
                  f"{sigma * interior_area(r['box']):.0f} | {r['step_bytes']:.0f} | "
                  f"{r['step_msgs']:.2f} | {r['build_bytes']:.0f} |")
    t_gs = float(os.environ.get("T_GS", "200e-9"))
    print(f"\nprediction (t_gs = {t_gs * 1e9:.0f} ns a grain-step on one core, T_GS):")
    print("| grains | processes | owned | ghosts | bytes a step | compute (us) | "
          "communication (us) | efficiency |")
    print("|---|---|---|---|---|---|---|---|")
    for n in (300_000, 10_000_000):
        for p in (8, 32, 128, 256, 1024):
            ghosts, compute, comm = step_time(n, p, sigma, bytes_per_ghost, t_gs)
            eff = n / p * t_gs / (compute + comm)
            print(f"| {n:,} | {p} | {n // p:,} | {ghosts:,.0f} | {ghosts * bytes_per_ghost:,.0f} "
                  f"| {compute * 1e6:,.0f} | {comm * 1e6:,.0f} | {eff:.2f} |")
    t_cyl = float(os.environ.get("T_GS_CYLINDER", "310e-9"))
    for p in (32, 256):
        ghosts, compute, comm = step_time(292_500, p, sigma, bytes_per_ghost, t_cyl)
        step = compute + comm
        print(f"full-scale cylinder on {p} processes: {step * 1e3:.2f} ms a step, 11.4 M steps in "
              f"{11.4e6 * step / 3600:.1f} h (t_gs {t_cyl * 1e9:.0f} ns)")


if __name__ == "__main__":
    main()
