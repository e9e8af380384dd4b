#!/usr/bin/python3
"""Draw the force network of a Sable run (like Dumont-Fortin-Ouafik's Figure 6).

Usage: plot_force_network.py OUT_DIR [PNG] [--step STEP] [--plane xz|xy|yz]

Reads OUT_DIR/vtk/grains_STEP.vtp and contacts_STEP.vtp (the last frame by default) and
draws the grains as circles and each contact as a segment between the two centres, its
width proportional to the normal force. 3D runs are projected on a plane (default xz).
Needs Debian's python3-matplotlib and python3-numpy.
"""
import argparse
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vtkxml  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402


def read_vtp(path):
    """Points and the named point/cell arrays of a VTK PolyData file (any encoding)."""
    f = vtkxml.read(path)
    return f.points, {**f.point_data, **f.cell_data}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("png", nargs="?")
    ap.add_argument("--step", type=int)
    ap.add_argument("--plane", default="xz", choices=["xz", "xy", "yz"])
    args = ap.parse_args()
    frames = sorted(glob.glob(os.path.join(args.out_dir, "vtk", "grains_*.vtp")))
    if not frames:
        raise SystemExit(f"{args.out_dir}: no vtk/grains_*.vtp frames found")
    stem = f"{args.step:010d}" if args.step is not None else frames[-1][-14:-4]
    grains, garrays = read_vtp(os.path.join(args.out_dir, "vtk", f"grains_{stem}.vtp"))
    contacts, carrays = read_vtp(os.path.join(args.out_dir, "vtk", f"contacts_{stem}.vtp"))
    is2d = np.all(grains[:, 2] == 0.0)
    axes = (0, 1) if is2d else {"xz": (0, 2), "xy": (0, 1), "yz": (1, 2)}[args.plane]
    fig, ax = plt.subplots(figsize=(6, 6))
    circles = [Circle((p[axes[0]], p[axes[1]]), r) for p, r in zip(grains, garrays["radius"])]
    ax.add_collection(PatchCollection(circles, facecolor="#eeeeee", edgecolor="#999999", lw=0.5))
    fn = np.abs(carrays.get("normal_force", np.zeros(0)))
    if fn.size:
        segs = contacts[:, axes].reshape(-1, 2, 2)
        widths = 0.3 + 5.0 * fn / fn.max() if fn.max() > 0 else np.full(fn.size, 0.3)
        ax.add_collection(LineCollection(segs, linewidths=widths, colors="#b2182b"))
    pad = garrays["radius"].max()
    ax.set_xlim(grains[:, axes[0]].min() - pad, grains[:, axes[0]].max() + pad)
    ax.set_ylim(grains[:, axes[1]].min() - pad, grains[:, axes[1]].max() + pad)
    ax.set_aspect("equal")
    ax.set_title(f"{os.path.basename(os.path.normpath(args.out_dir))}: step {int(stem)}, "
                 f"max normal force {fn.max() if fn.size else 0:.3g} N")
    png = args.png or os.path.join(args.out_dir, "force_network.png")
    fig.savefig(png, dpi=120, bbox_inches="tight")
    print(png)


if __name__ == "__main__":
    main()
