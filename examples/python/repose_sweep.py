#!/usr/bin/python3
"""The angle of repose of a heap of disks against their friction: a parameter sweep.

For each friction coefficient mu, 400 disks (d = 2 mm +- 10 %, restitution 0.1, rolling
friction 0.3 so that round grains can hold a slope) in a column 4 cm wide and 6 cm tall
collapse onto a rough floor (a row of fixed grains) and settle into a heap; the script then
takes the heap's surface (the highest grain top in each 1.5 d wide bin) and fits a line to
each flank between 20 % and 80 % of the heap's height. The angle is the mean of the two flanks' slopes. Runs are
independent Simulations built from one scenario text; the plot is OUT/repose.png. A demo of
a sweep, not a validation: a 2D heap of 400 disks is a noisy measure (a degree or two).

usage: repose_sweep.py [OUT] [MU ...]   (default out/python-repose, mu 0.1 0.3 0.5 0.7;
                                          a few seconds a run)
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sable  # noqa: E402

SCENARIO = """
[simulation]
dimension = 2
seed = 7
gravity = [0.0, -9.81]
thickness = 2e-3

[domain]
lo = [0.0, -0.002]
hi = [0.12, 0.14]

[[material]]
name = "grain"
density = 2500.0
young = 5e6
poisson = 0.45
restitution = 0.1
friction = {mu}
rolling_friction = {mu_r}

[contact]
rolling = "epsd"

[[grains]]
generator = "lattice"
material = "grain"
radius = 1e-3
spacing = 2e-3
region = {{ box = {{ lo = [0.0, -0.001], hi = [0.12, 0.001] }} }}
count = 60
fixed = true

[[grains]]
generator = "lattice"
material = "grain"
radius = {{ distribution = "uniform", mean = 1e-3, spread = 0.1 }}
spacing = 2.4e-3
jitter = 0.05e-3
region = {{ box = {{ lo = [0.04, 0.003], hi = [0.08, 0.063] }} }}
count = 400

[[wall]]
name = "floor"
type = "plane"
point = [0.0, -0.002]
normal = [0.0, 1.0]
material = "grain"

[[stage]]
name = "heap"
kinetic_energy_below = 1e-9
check_interval = 1000
max_steps = 200000
"""


MU_R = 0.3  # rolling friction (contact.rolling = "epsd"): round disks hold a slope with it


def flank_angle(x, top, lo, hi, centre):
    """Degrees of the line fitted to the surface points (x, top) with lo < top < hi."""
    pick = (top > lo) & (top < hi)
    if pick.sum() < 3:
        return float("nan")
    slope = np.polyfit(x[pick] - centre, top[pick], 1)[0]
    return math.degrees(math.atan(abs(slope)))


def repose_angle(g, d):
    """The heap's angle of repose (degrees) from the grains' positions and radii."""
    x, y = g["positions"][:, 0], g["positions"][:, 1]
    top = y + g["radii"]
    free = y > 0.0015  # the floor's fixed row is at y = 0
    edges = np.arange(x[free].min(), x[free].max() + 1.5 * d, 1.5 * d)
    cx, cy = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        inside = free & (x >= a) & (x < b)
        if inside.any():
            k = np.argmax(np.where(inside, top, -np.inf))
            cx.append(x[k])
            cy.append(top[k])
    cx, cy = np.array(cx), np.array(cy)
    height = cy.max()
    centre = cx[np.argmax(cy)]
    left, right = cx < centre, cx > centre
    lo, hi = 0.2 * height, 0.8 * height
    angles = [flank_angle(cx[s], cy[s], lo, hi, centre) for s in (left, right)]
    return float(np.nanmean(angles)), cx, cy


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/python-repose"
    mus = [float(m) for m in sys.argv[2:]] or [0.1, 0.3, 0.5, 0.7]
    os.makedirs(out, exist_ok=True)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    angles = []
    for mu in mus:
        sim = sable.Simulation(sable.Scenario.from_string(SCENARIO.format(mu=mu, mu_r=MU_R),
                                                          path=f"repose mu={mu}"),
                               outputs=False)
        sim.run()
        angle, cx, cy = repose_angle(sim.grains(), 2e-3)
        angles.append(angle)
        ax1.plot(cx * 100, cy * 100, ".-", label=f"mu = {mu}")
        print(f"mu = {mu}: angle of repose {angle:.1f} deg ({sim.steps} steps, "
              f"t = {sim.time:.2f} s)")
    ax1.set_xlabel("x (cm)")
    ax1.set_ylabel("surface height (cm)")
    ax1.set_aspect("equal")
    ax1.legend(fontsize="small", loc="upper right")
    ax2.plot(mus, angles, "o-")
    ax2.set_xlabel("friction coefficient mu")
    ax2.set_ylabel("angle of repose (deg)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "repose.png"), dpi=120)


if __name__ == "__main__":
    main()
