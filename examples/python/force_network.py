#!/usr/bin/python3
"""A snapshot's force network, read with sable.load_snapshot and drawn with matplotlib.

Each contact is a segment between the two grain centres, projected on a vertical plane, its
width proportional to the normal force (Radjai et al.'s strong and weak networks: the
segments above the mean force drawn dark, the others light); the grains are outlined. The
snapshot's arrays come without Sable's run: load_snapshot reads the file alone (positions,
radii, contacts with ids, normal forces).

usage: force_network.py SNAPSHOT.h5 [PNG]   (default PNG: beside the snapshot)
       (pour_live.py writes out/python-pour/settled.h5)
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

import sable  # noqa: E402


def main():
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    path = sys.argv[1]
    png = sys.argv[2] if len(sys.argv) > 2 else os.path.splitext(path)[0] + "_forces.png"
    s = sable.load_snapshot(path)
    x, r, ids = s["positions"], s["radii"], s["ids"]
    c = s["contacts"]
    slot = {int(i): k for k, i in enumerate(ids)}
    i = np.array([slot[int(a)] for a in c["id_i"]], dtype=int)
    j = np.array([slot[int(b)] for b in c["id_j"]], dtype=int)
    fn = c["normal_force"]
    # x and the vertical axis (z in 3D, y in 2D)
    up = 2 if s["dimension"] == 3 else 1
    segments = np.stack([x[i][:, [0, up]], x[j][:, [0, up]]], axis=1)
    mean = fn[fn > 0].mean()
    strong = fn > mean
    fig, ax = plt.subplots(figsize=(6, 6))
    for keep, colour in ((~strong, "0.7"), (strong, "k")):
        ax.add_collection(LineCollection(segments[keep], linewidths=3 * fn[keep] / fn.max(),
                                         colors=colour))
    ax.scatter(x[:, 0], x[:, up], s=1, c="tab:blue")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)" if up == 2 else "y (m)")
    ax.set_title(f"{len(r)} grains, {len(fn)} contacts, t = {s['time']:.3g} s")
    fig.savefig(png, dpi=120)
    print(f"{len(fn)} contacts, mean normal force {mean:.3g} N, {strong.mean():.1%} above the "
          f"mean carrying {fn[strong].sum() / fn[fn > 0].sum():.1%} of the total; {png}")


if __name__ == "__main__":
    main()
