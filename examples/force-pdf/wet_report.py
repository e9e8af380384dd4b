#!/usr/bin/python3
"""Wet force PDFs of Richefeu et al. (2009), section 4-5: the unconfined (0 Pa, their S6) and
confined (100 Pa, S7) wet packings of examples/force-pdf/wet.toml, analysed by run.sh.

Usage: wet_report.py OUT_DIR   (OUT_DIR = out/force-pdf; reads OUT_DIR/wet/analysis-0pa and
analysis-100pa, and OUT_DIR/iso-dem/analysis for the dry comparison if it exists)

Writes OUT_DIR/wet/summary.json and OUT_DIR/wet/wet.png and prints a table beside the paper's
values. Definitions (forces from contacts.csv, grain-grain contacts whose point lies in the
bulk region written by run.sh; compression positive):
  f0 = kappa R_max = 2 pi gamma R_max, the largest capillary force (paper eq. 10);
  alpha_w, compressive side: maximum likelihood of P(x) ~ exp(-alpha x), x = f_n / f0 > 0,
    i.e. 1 / mean(x);
  alpha_w, tensile side: the same for x = |f_n| / f0 on [0, 1] (the tensile range is cut at
    f0), the truncated-exponential likelihood 1/alpha - 1/(e^alpha - 1) = mean(x), solved by
    bisection;
  z = 2 N_c / N over the whole sample (sable analyze), split into compressive and tensile bonds;
  the tensile bonds split into those across a gap (the grains' distance above the sum of their
    radii: a pure capillary pull) and those at contacts, with the share and mean force of each;
  particle pressures p_i (sable analyze, eq. 11-13) over p0 = f0 / <d>^2, with the exponential
    rates of both sides (1 / mean |p| / p0) and the fraction of positive pressures;
  percolation of the positive and negative pressure phases (sable analyze percolation).
Debian's numpy and matplotlib only.
"""
import json
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from report import bulk_contacts, read_columns, read_region  # noqa: E402

GAMMA = 0.0728  # N/m, wet.toml's surface tension (theta = 0)
PAPER = {
    "alpha_w_0pa": 4.0,
    "z_0pa": 6.1,
    "z_compressive_0pa": 2.97,
    "z_tensile_0pa": 3.13,
    "notes": "Richefeu et al. 2009, section 4: at 0 Pa both sides of the PDF of f_n / f0 decay "
    "as exp(-alpha_w |f_n| / f0) with alpha_w ~ 4, a peak at f_n = 0, tensile forces cut at "
    "-f0, compressive ones up to ~2 f0; z ~ 6.1 = 2.97 compressive + 3.13 tensile; at 100 Pa "
    "the symmetry is broken, the compressive exponent close to the dry one; section 5: the "
    "particle-pressure PDF is symmetric about 0 with exponential sides, and the positive and "
    "negative phases each percolate.",
}


def truncated_rate(mean):
    """alpha with 1/alpha - 1/(e^alpha - 1) = mean on [0, 1] (mean < 1/2 gives alpha > 0)."""
    lo, hi = 1e-9, 200.0
    for _ in range(200):
        a = 0.5 * (lo + hi)
        m = 1 / a - 1 / np.expm1(a)
        lo, hi = (a, hi) if m > mean else (lo, a)
    return 0.5 * (lo + hi)


def mean_or_none(v):
    return float(v.mean()) if v.size else None


def state(out, label):
    adir = os.path.join(out, "wet", f"analysis-{label}")
    cli = json.load(open(os.path.join(adir, "summary.json")))
    region = read_region(os.path.join(out, "wet", f"region-{label}"))
    c, grain, inside, x, r, i, j = bulk_contacts(adir, region)
    f0 = 2 * np.pi * GAMMA * r.max()
    sel = grain & inside
    fn = c["fn_N"][sel]
    xc, xt = fn[fn > 0] / f0, -fn[fn < 0] / f0
    # A tensile bond is a bridge between touching grains whose attraction exceeds the elastic
    # repulsion, or a bridge across a gap (the pure capillary force kappa R e^(-gap / lambda)).
    gap = np.linalg.norm(x[i[sel]] - x[j[sel]], axis=1) - r[i[sel]] - r[j[sel]]
    at_gap = gap[fn < 0] > 0
    g = read_columns(os.path.join(adir, "particle_stress.csv"))
    p0 = f0 / (2 * r.mean()) ** 2
    pin = np.all((x >= region[0]) & (x <= region[1]), axis=1)
    pres = g["pressure_Pa"][pin] / p0
    co = cli["coordination"]
    perc = cli["percolation"]
    return {
        "f0_N": float(f0),
        "p0_Pa": float(p0),
        "bulk_contacts": int(len(fn)),
        "compressive": int(len(xc)),
        "tensile": int(len(xt)),
        "tensile_at_gaps_fraction": float(at_gap.mean()),
        "tensile_mean_at_gaps_over_f0": mean_or_none(xt[at_gap]),
        "tensile_mean_at_contacts_over_f0": mean_or_none(xt[~at_gap]),
        "compressive_mean_over_f0": float(xc.mean()),
        "alpha_w_compressive": float(1 / xc.mean()),
        "alpha_w_compressive_stderr": float(1 / xc.mean() / np.sqrt(len(xc))),
        "alpha_w_tensile": float(truncated_rate(xt.mean())),
        "max_compressive_over_f0": float(xc.max()),
        "max_tensile_over_f0": float(xt.max()),
        "mean_fn_over_f0": float(fn.mean() / f0),
        "z": co["z"],
        "z_compressive": co["z_compressive"],
        "z_tensile": co["z_tensile"],
        "rattler_fraction": co["rattler_fraction"],
        "pressure_positive_fraction": float(np.mean(pres > 0)),
        "pressure_rate_positive": float(1 / pres[pres > 0].mean()),
        "pressure_rate_negative": float(1 / -pres[pres < 0].mean()),
        "positive_phase_percolates": perc["positive"]["percolates"],
        "negative_phase_percolates": perc["negative"]["percolates"],
        "_x": np.concatenate([xc, -xt]),
        "_p": pres,
    }


def dry_alpha(out, f0):
    """The dry isotropic sample's compressive forces over the same f0 (the paper's S5 vs S7)."""
    adir = os.path.join(out, "iso-dem", "analysis")
    if not os.path.exists(os.path.join(adir, "contacts.csv")):
        return None, None
    region = read_region(os.path.join(out, "iso-dem", "region"))
    c, grain, inside, *_ = bulk_contacts(adir, region)
    fn = c["fn_N"][grain & inside]
    x = fn[fn > 0] / f0
    return float(1 / x.mean()), x


def pdf(x, edges):
    h, _ = np.histogram(x, bins=edges)
    d = h / (len(x) * np.diff(edges))
    mid = 0.5 * (edges[1:] + edges[:-1])
    return mid[d > 0], d[d > 0]


def figure(out, s0, s100, dry_x):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.3))
    edges = np.linspace(-1.05, 3.0, 82)
    for ax, s, title in ((axes[0], s0, "0 Pa (S6)"), (axes[1], s100, "100 Pa (S7)")):
        m, d = pdf(s["_x"], edges)
        ax.semilogy(m, d, "o", ms=3, color="tab:blue", label="wet, DEM")
        for side, rate, xs in (("compressive", s["alpha_w_compressive"], np.linspace(0, 3, 40)),
                               ("tensile", s["alpha_w_tensile"], np.linspace(-1, 0, 20))):
            frac = s[side] / (s["compressive"] + s["tensile"])
            norm = rate if side == "compressive" else rate / -np.expm1(-rate)
            ax.semilogy(xs, frac * norm * np.exp(-rate * np.abs(xs)), "-", color="tab:blue",
                        lw=1)
        ax.semilogy(np.linspace(-1, 2.5, 50), 0.9 * np.exp(-4 * np.abs(np.linspace(-1, 2.5, 50))),
                    "k:", label="paper's slope, alpha_w = 4")
        ax.set_title(f"wet, {title}: alpha_w = {s['alpha_w_tensile']:.1f} (tensile), "
                     f"{s['alpha_w_compressive']:.1f} (compressive)", fontsize=9)
        ax.set_xlabel("f_n / f0")
        ax.set_ylabel("P(f_n / f0)")
    if dry_x is not None:
        m, d = pdf(dry_x, edges)
        axes[1].semilogy(m, d, "s", ms=3, color="tab:gray", label="dry, 100 Pa (S5)")
    for ax in axes[:2]:
        ax.legend(fontsize=8)
    m, d = pdf(s0["_p"], np.linspace(-6, 6, 61))
    axes[2].semilogy(m, d, "o", ms=3, color="tab:purple")
    axes[2].set_xlabel("p_i / p0,  p0 = f0 / <d>^2")
    axes[2].set_ylabel("P(p_i / p0)")
    axes[2].set_title(f"particle pressures, 0 Pa: {100 * s0['pressure_positive_fraction']:.0f} % "
                      "positive", fontsize=9)
    fig.tight_layout()
    path = os.path.join(out, "wet", "wet.png")
    fig.savefig(path, dpi=120)
    return path


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/force-pdf"
    s0, s100 = state(out, "0pa"), state(out, "100pa")
    dry, dry_x = dry_alpha(out, s100["f0_N"])
    fig = figure(out, s0, s100, dry_x)
    run_seconds = float(open(os.path.join(out, "wet", "run_seconds")).read())
    strip = lambda s: {k: v for k, v in s.items() if not k.startswith("_")}  # noqa: E731
    summary = {"paper": PAPER, "run_seconds": run_seconds, "0pa": strip(s0),
               "100pa": strip(s100), "dry_100pa_alpha_compressive": dry}
    json.dump(summary, open(os.path.join(out, "wet", "summary.json"), "w"), indent=2)
    print(f"{'':28s} {'0 Pa':>8s} {'100 Pa':>8s} {'paper (0 Pa)':>13s}")
    rows = [("alpha_w tensile", "alpha_w_tensile", "~4"),
            ("alpha_w compressive", "alpha_w_compressive", "~4"),
            ("largest compressive / f0", "max_compressive_over_f0", "~2"),
            ("z", "z", "6.1"), ("z compressive", "z_compressive", "2.97"),
            ("z tensile", "z_tensile", "3.13"),
            ("tensile bonds at a gap (frac.)", "tensile_at_gaps_fraction", ""),
            ("mean |f_n| / f0 at gaps", "tensile_mean_at_gaps_over_f0", ""),
            ("mean |f_n| / f0 at contacts", "tensile_mean_at_contacts_over_f0", ""),
            ("positive pressures (frac.)", "pressure_positive_fraction", "~0.5")]
    num = lambda v: f"{v:8.2f}" if v is not None else f"{'-':>8s}"  # noqa: E731
    for label, key, paper in rows:
        print(f"{label:28s} {num(s0[key])} {num(s100[key])} {paper:>13s}")
    for label, key in (("positive phase percolates", "positive_phase_percolates"),
                       ("negative phase percolates", "negative_phase_percolates")):
        fmt = lambda p: "".join(a for a in "xyz" if p[a]) or "no"  # noqa: E731
        print(f"{label:28s} {fmt(s0[key]):>8s} {fmt(s100[key]):>8s} {'both':>13s}")
    if dry is not None:
        print(f"dry 100 Pa compressive alpha over the same f0: {dry:.2f} "
              f"(wet 100 Pa: {s100['alpha_w_compressive']:.2f}; paper: nearly the same)")
    print(f"run {run_seconds:.0f} s; wrote {os.path.join(out, 'wet', 'summary.json')} and {fig}")


if __name__ == "__main__":
    main()
