#!/usr/bin/python3
"""Figures for the tables `sable analyze` writes: one PNG beside each CSV.

Usage: /usr/bin/python3 scripts/plot_analysis.py ANALYSIS_DIR

Reads summary.json and the CSV files of ANALYSIS_DIR (see docs/analysis.md for what each
holds) and writes NAME.png next to NAME.csv. Uses Debian's python3-numpy and
python3-matplotlib only.
"""
import json
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    with open(path) as f:
        names = f.readline().strip().split(",")
    data = np.genfromtxt(path, delimiter=",", skip_header=1, ndmin=2)
    if data.size == 0:
        data = np.zeros((0, len(names)))
    return {n: data[:, k] for k, n in enumerate(names)}


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print("wrote", path)


def get(summary, *keys):
    for k in keys:
        if not isinstance(summary, dict) or k not in summary:
            return None
        summary = summary[k]
    return summary


def plot_force_pdf(t, name, summary, out):
    side = name[len("force_pdf_"):]
    comp = "tangential" if side == "tangential" else "normal"
    xcol = [c for c in t if c.endswith("_lo")][0][:-3]
    x, pdf = t[xcol], t["pdf"]
    fig, ax = plt.subplots(figsize=(5, 4))
    keep = pdf > 0
    ax.semilogy(x[keep], pdf[keep], "o", ms=4, label="Sable")
    beta = get(summary, "forces", comp, "sides", side, "tail", "beta_mle")
    if beta:
        frac_tail = np.sum(pdf[x > 1]) * (x[1] - x[0]) if len(x) > 1 else 0
        xs = np.linspace(1, max(x.max(), 1.01), 50)
        ax.semilogy(xs, frac_tail * beta * np.exp(-beta * (xs - 1)), "-",
                    label=f"exp(-{beta:.2f} x), x > 1 (max. likelihood)")
    ax.set_xlabel(xcol.replace("_", " "))
    ax.set_ylabel("PDF")
    ax.set_title(f"{comp} forces: {side}")
    ax.legend(fontsize=8)
    save(fig, out)


def plot_histogram(t, xcol, ycol, xlabel, title, out, log=False):
    fig, ax = plt.subplots(figsize=(5, 4))
    x, y = t[xcol], t[ycol]
    width = (x[1] - x[0]) if len(x) > 1 else 1.0
    ax.bar(x, y, width=width * 0.95)
    if log:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ycol.replace("_", " "))
    ax.set_title(title)
    save(fig, out)


def plot_fabric(t, out):
    fig = plt.figure(figsize=(5, 4))
    if "angle_deg" in t:
        ax = fig.add_subplot(projection="polar")
        th = np.radians(t["angle_deg"])
        r = t["over_isotropic"]
        ax.bar(np.concatenate([th, th + np.pi]), np.concatenate([r, r]),
               width=np.radians(t["angle_hi_deg"][0] - t["angle_lo_deg"][0]))
        ax.set_title("contact orientations / isotropic")
    else:
        ax = fig.add_subplot()
        xcol = [c for c in t if c.endswith("_deg") and not c.endswith(("_lo_deg", "_hi_deg"))][0]
        ycol = "over_isotropic" if "over_isotropic" in t else [c for c in t if c.startswith("pdf")][0]
        ax.bar(t[xcol], t[ycol], width=np.diff(t[xcol]).mean() * 0.95)
        if ycol == "over_isotropic":
            ax.axhline(1, color="k", lw=0.8)
        ax.set_xlabel(xcol.replace("_", " "))
        ax.set_ylabel(ycol.replace("_", " "))
    save(fig, out)


def plot_wall_profile(t, name, out):
    fig, ax = plt.subplots(figsize=(5, 4))
    d = t["depth_m"]
    ax.plot(t["normal_stress_Pa"], d, "o-", ms=3, label="normal stress")
    ax.plot(t["shear_stress_Pa"], d, "s-", ms=3, label="shear stress (upward on grains)")
    ax.invert_yaxis()
    ax.set_xlabel("stress (Pa)")
    ax.set_ylabel("depth below the top of the packing (m)")
    ax.set_title(name.replace("wall_profile_", "wall "))
    ax.legend(fontsize=8)
    save(fig, out)


def plot_fields(t, out):
    fig, axes = plt.subplots(1, 2, figsize=(9, 4))
    if "s_m" in t:
        s = t["s_m"]
        axes[0].plot(s, t["pressure_Pa"], label="pressure")
        axes[0].plot(s, t["deviator_Pa"], label="max shear")
        axes[0].set_xlabel("distance along the line (m)")
        axes[0].set_ylabel("Pa")
        axes[0].legend(fontsize=8)
        axes[1].plot(s, t["volume_fraction"])
        axes[1].set_xlabel("distance along the line (m)")
        axes[1].set_ylabel("volume fraction")
    else:
        # Grid: a vertical cut through the middle (the last axis is up for piles and silos).
        axes_names = [a for a in ("x_m", "y_m", "z_m") if a in t]
        h, v = axes_names[0], axes_names[-1]
        if len(axes_names) == 3:
            mid = np.unique(t["y_m"])[len(np.unique(t["y_m"])) // 2]
            sel = t["y_m"] == mid
        else:
            sel = np.ones(len(t[h]), bool)
        hs, vs = np.unique(t[h][sel]), np.unique(t[v][sel])
        for ax, col, label in ((axes[0], "pressure_Pa", "pressure (Pa)"),
                               (axes[1], "volume_fraction", "volume fraction")):
            # Nodes are stored x fastest: the cut is a regular (v, h) array.
            values = t[col][sel].reshape(len(vs), len(hs))
            mesh = ax.pcolormesh(hs, vs, values, shading="nearest")
            fig.colorbar(mesh, ax=ax, label=label)
            ax.set_xlabel(h)
            ax.set_ylabel(v)
            ax.set_aspect("equal")
    save(fig, out)


def plot_percolation(directory, out):
    perc = read_csv(os.path.join(directory, "percolation.csv"))
    ps_path = os.path.join(directory, "particle_stress.csv")
    if not os.path.exists(ps_path):
        return
    ps = read_csv(ps_path)
    x, y = ps["x_m"], ps["y_m"]
    sel = np.ones(len(x), bool)
    if "z_m" in ps:  # 3D: a slab of two mean diameters through the middle in y
        ymid, d = np.median(ps["y_m"]), 4 * np.mean(ps["radius_m"])
        sel = np.abs(ps["y_m"] - ymid) < d
        y = ps["z_m"]
    fig, ax = plt.subplots(figsize=(5, 5))
    colours = np.where(perc["phase"] > 0, "k", np.where(perc["phase"] < 0, "0.8", "r"))
    ax.scatter(x[sel], y[sel], c=colours[sel], s=(ps["radius_m"][sel] / ps["radius_m"].max()) * 20)
    ax.set_aspect("equal")
    ax.set_title("particle pressure > 0 (black), < 0 (grey)")
    save(fig, out)


def plot_janssen(t, summary, out):
    j = summary.get("janssen", {})
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(t["wall_normal_stress_Pa"], t["depth_m"], "o", label="side walls (measured)")
    if j.get("K"):
        z = np.linspace(0, t["depth_m"].max() * 1.05, 100)
        ax.plot(j["saturation_wall_stress_Pa"] * (1 - np.exp(-z / j["lambda_m"])), z, "-",
                label=f"Janssen K = {j['K']:.2f} +- {j['K_stderr']:.2f}, R2 = {j['r2']:.2f}")
    ax.invert_yaxis()
    ax.set_xlabel("wall normal stress (Pa)")
    ax.set_ylabel("depth (m)")
    ax.legend(fontsize=8)
    save(fig, out)


def plot_contacts(t, out):
    from matplotlib.collections import LineCollection
    three = "z_i_m" in t
    v = "z" if three else "y"
    xi, yi, xe, ye = t["x_i_m"], t[v + "_i_m"], t["x_end_m"], t[v + "_end_m"]
    keep = np.ones(len(xi), bool)
    if three:  # a slab through the middle in y
        keep = np.abs(t["y_i_m"] - np.median(t["y_i_m"])) < 0.05 * np.ptp(t["y_i_m"]) + 1e-12
    fn = t["fn_N"][keep]
    segs = np.stack([np.stack([xi[keep], yi[keep]], 1), np.stack([xe[keep], ye[keep]], 1)], 1)
    on = np.nan_to_num(t["mobilisation"][keep]) >= 0.99
    fig, ax = plt.subplots(figsize=(5, 6))
    ax.add_collection(LineCollection(segs, linewidths=0.3 + 3 * fn / max(fn.max(), 1e-300),
                                     colors=np.where(on, "tab:red", "0.5")))
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_title("contact network: width ~ fn, red = on the Coulomb cone", fontsize=9)
    save(fig, out)


def plot_series(t, out):
    # One panel per scalar; the walls' columns (wall_NAME_f?_N, wall_NAME_t?_Nm) one panel per
    # wall for its force components and one for its torque's.
    panels = []
    for c in t:
        if c in ("time_s", "step"):
            continue
        m = re.fullmatch(r"wall_(.*)_([ft])[xyz]_Nm?", c)
        key = (m.group(1), m.group(2)) if m else c
        for p in panels:
            if p[0] == key:
                p[1].append(c)
                break
        else:
            panels.append((key, [c]))
    fig, axes = plt.subplots(len(panels), 1, figsize=(6, 1.8 * len(panels)), sharex=True)
    axes = np.atleast_1d(axes)
    for ax, (key, cols) in zip(axes, panels):
        for c in cols:
            label = re.fullmatch(r"wall_.*_([ft][xyz])_Nm?", c)
            ax.plot(t["time_s"], t[c], "o-", ms=3, label=label.group(1) if label else None)
        if isinstance(key, tuple):
            ax.set_ylabel(f"wall {key[0]}\n{'force (N)' if key[1] == 'f' else 'torque (N m)'}",
                          fontsize=8)
            ax.legend(fontsize=7)
        else:
            ax.set_ylabel(key.replace("_", " "), fontsize=8)
    axes[-1].set_xlabel("time (s)")
    save(fig, out)


def main(directory):
    summary_path = os.path.join(directory, "summary.json")
    if not os.path.exists(summary_path):
        sys.exit(f"{directory}: no summary.json here; is this a `sable analyze` output directory?")
    with open(summary_path) as f:
        summary = json.load(f)
    for fname in sorted(os.listdir(directory)):
        if not fname.endswith(".csv"):
            continue
        name = fname[:-4]
        out = os.path.join(directory, name + ".png")
        t = read_csv(os.path.join(directory, fname))
        if name.startswith("force_pdf_"):
            plot_force_pdf(t, name, summary, out)
        elif name == "pressure_pdf":
            plot_histogram(t, "p_over_mean_abs", "pdf", "p / <|p|>", "particle pressures", out,
                           log=True)
        elif name.startswith("polarization_"):
            plot_histogram(t, "m", "pdf", "|ft| / (mu fn)", name.replace("_", " "), out)
        elif name == "coordination":
            plot_histogram(t, "contacts", "fraction", "force-carrying contacts per grain",
                           "coordination", out)
        elif name.startswith("fabric"):
            plot_fabric(t, out)
        elif name.startswith("wall_profile_"):
            plot_wall_profile(t, name, out)
        elif name in ("fields", "fields_line"):
            plot_fields(t, out)
        elif name == "percolation":
            plot_percolation(directory, out)
        elif name == "series":
            plot_series(t, out)
        elif name == "janssen":
            plot_janssen(t, summary, out)
        elif name == "contacts":
            plot_contacts(t, out)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
