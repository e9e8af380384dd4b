#!/usr/bin/python3
"""Summary and figure of the silo study (examples/silo-janssen/run.sh).

Usage: /usr/bin/python3 examples/silo-janssen/report.py OUT_DIR CASE [CASE ...]
(the large case writes summary-large.json and silo-janssen-large.png instead)

Reads OUT_DIR/CASE/{before,relax,after}/summary.json (written by `sable analyze`), the fitted
profile OUT_DIR/CASE/relax/janssen.csv and the contact network OUT_DIR/CASE/relax/contacts.csv,
and writes OUT_DIR/summary.json and OUT_DIR/silo-janssen.png (the paper's Figure 7: the force
network coloured by the mobilisation of friction, beside the side-wall normal stress against
depth with Janssen's fitted curve). Debian's python3-numpy and python3-matplotlib only.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402


def load(path):
    with open(path) as f:
        return json.load(f)


def read_csv(path):
    with open(path) as f:
        names = f.readline().strip().split(",")
    data = np.genfromtxt(path, delimiter=",", skip_header=1, ndmin=2)
    return {n: data[:, k] for k, n in enumerate(names)}


def side_walls(summary):
    """Names of the walls that got a height profile (the side walls)."""
    return sorted(summary.get("walls", {}).keys())


def pooled_fraction(summary, walls):
    """Fraction of the side walls' compressive contacts on the Coulomb cone, pooled."""
    sliding = count = 0
    for w in walls:
        p = summary["polarization"].get("wall_" + w, {})
        sliding += p.get("sliding", 0)
        count += p.get("count", 0)
    return (sliding / count if count else float("nan")), count


def shear_over_normal(summary, walls):
    n = sum(summary["walls"][w]["total_normal_force_N"] for w in walls)
    t = sum(summary["walls"][w]["total_shear_force_N"] for w in walls)
    return t / n if n else float("nan")


def case_summary(out, case):
    res = {}
    for phase in ("before", "relax", "after"):
        s = load(os.path.join(out, case, phase, "summary.json"))
        walls = side_walls(s)
        frac, count = pooled_fraction(s, walls)
        bulk = s["polarization"].get("bulk", {})
        j = s.get("janssen", {})
        res[phase] = {
            "snapshots": s["inputs"],
            "wall_contacts": count,
            "wall_fraction_on_cone": frac,
            "bulk_fraction_on_cone": bulk.get("fraction_sliding"),
            "wall_shear_over_normal": shear_over_normal(s, walls),
            "wall_friction": j.get("wall_friction"),
            "support_over_weight": j.get("support_over_weight"),
            "floor_stress_Pa": j.get("floor_stress_Pa"),
        }
        if phase == "relax":
            res["janssen"] = j
    seconds = os.path.join(out, case, "run_seconds")
    if os.path.exists(seconds):
        res["run_seconds"] = float(open(seconds).read())
    return res


def draw_network(ax, contacts_csv, title):
    c = read_csv(contacts_csv)
    three = "z_i_m" in c
    xi, yi = c["x_i_m"], c["z_i_m"] if three else c["y_i_m"]
    xe, ye = c["x_end_m"], c["z_end_m"] if three else c["y_end_m"]
    if three:  # a slab through the middle, two mean diameters thick
        mid = np.median(c["y_i_m"])
        keep = np.abs(c["y_i_m"] - mid) < 3e-3
        xi, yi, xe, ye = xi[keep], yi[keep], xe[keep], ye[keep]
        fn, m = c["fn_N"][keep], c["mobilisation"][keep]
    else:
        fn, m = c["fn_N"], c["mobilisation"]
    segs = np.stack([np.stack([xi, yi], 1), np.stack([xe, ye], 1)], 1)
    width = 0.3 + 3.0 * fn / max(fn.max(), 1e-300)
    on = np.nan_to_num(m) >= 0.99
    lc = LineCollection(segs, linewidths=width, colors=np.where(on, "tab:red", "0.55"))
    ax.add_collection(lc)
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)" if three else "y (m)")
    ax.set_title(title, fontsize=9)


def draw_profiles(ax, out, cases, summary):
    styles = ["o", "s", "^", "v"]
    for k, case in enumerate(cases):
        j = summary[case].get("janssen", {})
        t = read_csv(os.path.join(out, case, "relax", "janssen.csv"))
        ax.plot(t["wall_normal_stress_Pa"], t["depth_m"], styles[k % 4], label=f"{case}: measured")
        z = np.linspace(0, max(t["depth_m"]) * 1.05, 100)
        colour = ax.lines[-1].get_color()
        if j.get("K"):
            fit = j["saturation_wall_stress_Pa"] * (1 - np.exp(-z / j["lambda_m"]))
            ax.plot(fit, z, "-", color=colour, label=f"{case}: Janssen, mu_w = "
                    f"{j['wall_friction']:.2f}: K = {j['K']:.2f} +- {j['K_stderr']:.2f}, "
                    f"R2 = {j['r2']:.2f}")
        m = j.get("with_mobilised_friction", {})
        if m.get("K"):
            fit = m["saturation_wall_stress_Pa"] * (1 - np.exp(-z / m["lambda_m"]))
            ax.plot(fit, z, "--", color=colour, label=f"{case}: Janssen, mobilised mu = "
                    f"{m['wall_friction']:.2f}: K = {m['K']:.2f} +- {m['K_stderr']:.2f}, "
                    f"R2 = {m['r2']:.2f}")
        if k > 0:
            continue
        before = os.path.join(out, case, "before")
        walls = side_walls(load(os.path.join(before, "summary.json")))
        if walls:
            b = [read_csv(os.path.join(before, f"wall_profile_{w.replace('.', '_')}.csv"))
                 for w in walls]
            sig = np.mean([p["normal_stress_Pa"] for p in b], axis=0)
            ax.plot(sig, b[0]["depth_m"], ":", color="0.5", label=f"{case}: before relaxation")
    ax.invert_yaxis()
    ax.set_xlabel("side-wall normal stress (Pa)")
    ax.set_ylabel("depth below the free surface (m)")
    ax.legend(fontsize=6.5, loc="upper right")


def main(out, cases):
    tag = "-large" if cases == ["dem-2d-large"] else ""
    summary = {case: case_summary(out, case) for case in cases}
    ks = {c: summary[c]["janssen"] for c in cases if summary[c].get("janssen", {}).get("K")}
    for suffix in ("", "-rolling"):
        cd, dem = "cd-2d" + suffix, "dem-2d" + suffix
        if cd not in ks or dem not in ks:
            continue
        a, b = ks[cd], ks[dem]
        diff = abs(a["K"] - b["K"])
        se = math.hypot(a["K_stderr"], b["K_stderr"])
        summary["cd_vs_dem_2d" + suffix.replace("-", "_")] = {
            "K_difference": diff, "combined_stderr": se, "within_2_sigma": diff < 2 * se}
    with open(os.path.join(out, f"summary{tag}.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(json.dumps(summary, indent=2))
    fig, axes = plt.subplots(1, 2, figsize=(11, 6), gridspec_kw={"width_ratios": [1, 1.4]})
    first = cases[0]
    frac = summary[first]["relax"]["wall_fraction_on_cone"]
    draw_network(axes[0], os.path.join(out, first, "relax", "contacts.csv"),
                 f"{first}, end of the descent: red = on the Coulomb cone\n"
                 f"(side-wall contacts on the cone: {100 * frac:.0f} %)")
    draw_profiles(axes[1], out, cases, summary)
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"silo-janssen{tag}.png"), dpi=120)
    print("wrote", os.path.join(out, f"silo-janssen{tag}.png"))


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
