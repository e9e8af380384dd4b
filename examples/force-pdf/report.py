#!/usr/bin/python3
"""Force PDFs of Richefeu et al. (2009): summary.json, the figure and a table, from the runs
and analyses of examples/force-pdf/run.sh.

Usage: report.py OUT_DIR [CASE...]   (OUT_DIR = out/force-pdf; every analysed case is reported)

Cases: iso-dem, triaxial-dem (DEM, soft grains) and iso-cd, triaxial-cd (contact dynamics, rigid
grains: iso-dem's end state relaxed by CD, then compressed by CD); iso-poly-cd (the paper's S3:
convex polyhedra compacted and relaxed by CD). The axial strain of a
triaxial case is measured from the end state of its own isotropic case (iso-dem for
triaxial-dem, iso-cd for triaxial-cd).

Statistics are over the bulk: the region of OUT_DIR/CASE/region (the sample's box less two mean
diameters on every side, written by run.sh). They are computed here from `sable analyze`'s
contacts.csv (grain-grain contacts whose contact point, contacts.csv's x_c_m..., or
r_i / (r_i + r_j) along the branch in an older file, lies in the region) and particle_stress.csv (positions and
radii), with the analysis' own definitions (docs/analysis.md section 1): x = f_n / <f_n>,
beta = 1 / mean(x - 1) over x > 1 (maximum likelihood, standard error beta / sqrt(n)), the
fraction with x < 1, P(0) = the density over [0, 0.1), and the weak forces' power law
P(x) ~ x^alpha: the least-squares slope of log P against log x over 8 logarithmic bins of
[0.01, 1) (alpha < 0: a density that decreases, the paper's S3). `sable analyze --region` now restricts
its force PDF to the same contacts (grain-grain, point in the region), so its values (reported
as "whole_sample_cli", the name kept for the file's readers) agree with the bulk ones here;
its coordination is still over the whole sample, hence bulk_coordination below. Debian's numpy and matplotlib only.
"""
import csv
import json
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PAPER = {
    "beta": 1.4,
    "fraction_below_mean_min": 0.60,
    "beta_polyhedra": 0.97,
    "notes": "Richefeu et al. 2009, section 3: beta ~ 1.4 for MD and CD isotropic samples and "
    "nearly unchanged after triaxial compression; > 60 % of the forces below the mean; "
    "isotropic: a small peak slightly below the mean and a finite P(0); anisotropic: the peak "
    "disappears and the weak forces become nearly uniform. Polyhedra (S3, CD, isotropic, "
    "Fig. 4): beta = 0.97 and a decreasing power law for the weak forces.",
}
KNOWN = ["iso-dem", "triaxial-dem", "iso-cd", "triaxial-cd", "iso-poly-cd", "s3-cd", "wet-0pa",
         "wet-100pa"]
# The isotropic state each triaxial case starts from: its axial-strain reference.
ISO_OF = {"triaxial-dem": "iso-dem", "triaxial-cd": "iso-cd"}
COLORS = {"iso-dem": "tab:blue", "triaxial-dem": "tab:red", "iso-cd": "tab:cyan",
          "triaxial-cd": "tab:orange", "iso-poly-cd": "tab:green", "s3-cd": "tab:olive"}
LABELS = {"iso-dem": "isotropic, DEM", "triaxial-dem": "anisotropic (triaxial), DEM",
          "iso-cd": "isotropic, CD", "triaxial-cd": "anisotropic (triaxial), CD",
          "iso-poly-cd": "polyhedra, isotropic, CD", "s3-cd": "20,000 polyhedra (S3), CD"}
P0_WINDOW = 0.1
P_M = 100.0  # Pa, the confining pressure of the dry cases


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head, body = rows[0], np.array(rows[1:], dtype=float)
    return {name: body[:, k] for k, name in enumerate(head)}


def read_region(path):
    lo, hi = open(path).read().strip().split(":")
    return np.array(lo.split(","), dtype=float), np.array(hi.split(","), dtype=float)


def bulk_contacts(adir, region):
    """Grain-grain force-carrying contacts with their point in the region, and the grains."""
    c = read_columns(os.path.join(adir, "contacts.csv"))
    g = read_columns(os.path.join(adir, "particle_stress.csv"))
    # contacts.csv names its grains by storage slot (i, and partner for a grain-grain row),
    # and particle_stress.csv has one row per slot, in slot order. Its `id` column is another
    # numbering: a run sorts the slots by cell (reorder_every), the ids stay with the grains.
    x = np.stack([g["x_m"], g["y_m"], g["z_m"]], axis=1)
    r = g["radius_m"]
    i = c["i"].astype(int)
    j = c["partner"].astype(int)
    grain = c["wall"] == 0
    xi = np.stack([c["x_i_m"], c["y_i_m"], c["z_i_m"]], axis=1)
    # Both files print the same doubles with the same format: every contact's first end is
    # exactly its slot's row, or the two files do not index the grains alike.
    if i.size and (i.max() >= len(r) or np.any(j[grain] >= len(r)) or
                   not np.array_equal(x[i], xi)):
        raise SystemExit(f"{adir}: contacts.csv's grain slots do not match the rows of "
                         "particle_stress.csv")
    lo, hi = region
    if "x_c_m" in c:
        point = np.stack([c["x_c_m"], c["y_c_m"], c["z_c_m"]], axis=1)
    else:
        xe = np.stack([c["x_end_m"], c["y_end_m"], c["z_end_m"]], axis=1)
        partner = np.where(grain, j, 0)  # a wall's row names the wall: any grain will do there
        share = np.where(grain, r[i] / (r[i] + r[partner]), 0.0)
        point = xi + share[:, None] * (xe - xi)
    inside = np.all((point >= lo) & (point <= hi), axis=1)
    return c, grain, inside, x, r, i, j


def force_stats(fn):
    """The analysis' definitions over compressive normal forces fn (N)."""
    fn = fn[fn > 0]
    x = fn / fn.mean()
    tail = x[x > 1] - 1
    beta = 1 / tail.mean()
    weak_edges = np.linspace(0, 1.5, 16)
    weak, _ = np.histogram(x, bins=weak_edges)
    weak = weak / (len(x) * np.diff(weak_edges))
    peak = int(np.argmax(weak))
    log_edges = np.logspace(-2, 0, 9)
    counts, _ = np.histogram(x, bins=log_edges)
    dens = counts / (len(x) * np.diff(log_edges))
    centre = np.sqrt(log_edges[1:] * log_edges[:-1])
    ok = counts > 0
    alpha = float(np.polyfit(np.log(centre[ok]), np.log(dens[ok]), 1)[0]) if ok.sum() > 2 else None
    return {
        "contacts": int(len(x)),
        "mean_force_N": float(fn.mean()),
        "beta_mle": float(beta),
        "beta_mle_stderr": float(beta / np.sqrt(len(tail))),
        "n_tail": int(len(tail)),
        "fraction_below_mean": float(np.mean(x < 1)),
        "p0": float(np.sum(x < P0_WINDOW) / (len(x) * P0_WINDOW)),
        "p0_window": P0_WINDOW,
        # Weak forces: the density in bins of 0.1 over [0, 1.5), where it peaks, and how flat
        # it is below the mean (lowest over highest of the bins below x = 1).
        "weak_pdf": [float(v) for v in weak],
        "weak_peak_at": float(0.5 * (weak_edges[peak] + weak_edges[peak + 1])),
        "weak_peak_over_p0": float(weak[peak] / weak[0]) if weak[0] > 0 else None,
        "weak_flatness_below_mean": float(weak[:10].min() / weak[:10].max()),
        "weak_power_law_exponent": alpha,
        "weak_log_pdf": [[float(c), float(d)] for c, d in zip(centre[ok], dens[ok])],
        "x": x,
    }


def coordination(c, grain, x, region, i, j, n):
    """z of the grains with their centre in the region (all their contacts, walls included),
    and without rattlers (fewer than 3 contacts: z over contacts between non-rattlers)."""
    lo, hi = region
    count = np.bincount(i, minlength=n) + np.bincount(j[grain], minlength=n)
    inside = np.all((x >= lo) & (x <= hi), axis=1)
    rattler = count < 3
    both = grain & ~rattler[i] & ~rattler[np.where(grain, j, 0)]
    kept = np.bincount(i[both], minlength=n) + np.bincount(j[both], minlength=n)
    sel = inside & ~rattler
    return {
        "grains": int(inside.sum()),
        "z": float(count[inside].mean()),
        "rattler_fraction": float(rattler[inside].mean()),
        "z_without_rattlers": float(kept[sel].mean()),
    }


def box_history(run_dir, start=None):
    s = read_columns(os.path.join(run_dir, "series.csv"))
    out = {k: float(s[k][-1]) for k in ("sigma_xx_Pa", "sigma_yy_Pa", "sigma_zz_Pa",
                                        "solid_fraction")}
    out["step"] = int(s["step"][-1])
    if start is not None:  # triaxial: axial strain since the isotropic state, and q/p
        lz0 = start["box_zhi_m"][-1] - start["box_zlo_m"][-1]
        lz = s["box_zhi_m"] - s["box_zlo_m"]
        eps = 1 - lz / lz0
        lateral = 0.5 * (s["sigma_xx_Pa"] + s["sigma_yy_Pa"])
        p = (s["sigma_zz_Pa"] + 2 * lateral) / 3
        q = s["sigma_zz_Pa"] - lateral
        out["axial_strain"] = float(eps[-1])
        out["axial_strain_rate_per_s"] = float(np.polyfit(s["time_s"], eps, 1)[0])
        out["q_over_p_end"] = float(q[-1] / p[-1])
        out["q_over_p_peak"] = float(np.max(q / p))
        out["q_over_p_peak_at_strain"] = float(eps[np.argmax(q / p)])
        out["curve"] = (eps, q / p, s["solid_fraction"])
        # How well the servo holds the lateral walls at p_m once the compression is under way.
        late = eps > 0.01
        for k in ("sigma_xx_Pa", "sigma_yy_Pa") if late.any() else ():
            out[f"max_rel_error_{k[:8]}_after_1pct"] = float(np.max(np.abs(s[k][late] / P_M - 1)))
    return out


def report_case(out, name, iso_series):
    run_dir, adir = os.path.join(out, name), os.path.join(out, name, "analysis")
    region = read_region(os.path.join(run_dir, "region"))
    cli = json.load(open(os.path.join(adir, "summary.json")))
    c, grain, inside, x, r, i, j = bulk_contacts(adir, region)
    bulk = force_stats(c["fn_N"][grain & inside])
    comp = cli["forces"]["normal"]["sides"]["compressive"]
    res = {
        "region": open(os.path.join(run_dir, "region")).read().strip(),
        "run_seconds": float(open(os.path.join(run_dir, "run_seconds")).read()),
        "bulk": {k: v for k, v in bulk.items() if k != "x"},
        "bulk_coordination": coordination(c, grain, x, region, i, j, len(r)),
        "whole_sample_cli": {
            "beta_mle": comp["tail"]["beta_mle"],
            "beta_mle_stderr": comp["tail"]["beta_mle_stderr"],
            "beta_lsq": comp["tail"]["beta_lsq"],
            "fraction_below_mean": comp["fraction_below_mean"],
            "p0": comp["p0"],
            "z": cli["coordination"]["z"],
            "z_without_rattlers": cli["coordination"]["z_without_rattlers"],
            "rattler_fraction": cli["coordination"]["rattler_fraction"],
        },
        "fabric_anisotropy_region": cli["fabric"]["anisotropy"],
        "love_weber_principal_Pa_region": cli["stress"]["love_weber"]["principal_Pa"],
        "positive_pressure_percolates": cli["percolation"]["positive"]["percolates"],
        "box": box_history(run_dir, iso_series.get(ISO_OF.get(name))),
    }
    return res, bulk["x"]


def figure(out, xs, results):
    tri = [n for n in results if n.startswith("triaxial")]
    fig, axes = plt.subplots(1, 3 if tri else 2, figsize=(16 if tri else 11, 4.3))
    a, w = axes[0], axes[1]
    for name, x in xs.items():
        edges = np.linspace(0, 7, 36)
        h, _ = np.histogram(x, bins=edges)
        pdf = h / (len(x) * np.diff(edges))
        mid = 0.5 * (edges[1:] + edges[:-1])
        ok = pdf > 0
        bk = results[name]["bulk"]
        label = LABELS.get(name, name)
        col = COLORS.get(name)
        a.semilogy(mid[ok], pdf[ok], "o" if name.endswith("dem") else "s", ms=4, color=col,
                   mfc=col if name.endswith("dem") else "none",
                   label=f"{label}: beta = {bk['beta_mle']:.2f}")
        # The fitted truncated exponential over x > 1: P(x) = P(x > 1) beta e^(-beta (x - 1)).
        xt = np.linspace(1, 7, 50)
        frac = 1 - bk["fraction_below_mean"]
        a.semilogy(xt, frac * bk["beta_mle"] * np.exp(-bk["beta_mle"] * (xt - 1)), "-", color=col)
        lw = np.array(bk["weak_log_pdf"])
        if len(lw):
            alpha = bk["weak_power_law_exponent"]
            w.loglog(lw[:, 0], lw[:, 1], "o-" if name.endswith("dem") else "s-", ms=4, color=col,
                     mfc=col if name.endswith("dem") else "none",
                     label=f"{label}: alpha = {alpha:.2f}" if alpha is not None else label)
    xt = np.linspace(1, 7, 50)
    a.semilogy(xt, 0.38 * 1.4 * np.exp(-1.4 * (xt - 1)), "k:", label="slope of the paper's beta = 1.4")
    if any("poly" in n for n in xs):
        a.semilogy(xt, 0.36 * 0.97 * np.exp(-0.97 * (xt - 1)), "k--",
                   label="slope of the paper's beta = 0.97 (polyhedra)")
    w.set_xlabel("f_n / <f_n>")
    w.set_ylabel("P(f_n / <f_n>)")
    w.set_title("weak forces, bulk: P ~ x^alpha over [0.01, 1)")
    w.legend(fontsize=8)
    a.set_xlabel("f_n / <f_n>")
    a.set_ylabel("P(f_n / <f_n>)")
    a.set_title("normal forces, bulk (2 <d> from the walls)")
    a.legend(fontsize=8)
    if tri:
        b = axes[2]
        b2 = b.twinx()
        for n in tri:
            eps, qp, phi = results[n]["box"].pop("curve")
            kind = "DEM" if n.endswith("dem") else "CD"
            b.plot(100 * eps, qp, color=COLORS.get(n), label=f"q / p, {kind}")
            b2.plot(100 * eps, phi, color=COLORS.get(n), ls="--", alpha=0.6,
                    label=f"solid fraction, {kind}")
        b.set_xlabel("axial strain (%)")
        b.set_ylabel("q / p (solid)")
        b2.set_ylabel("solid fraction (dashed)", color="tab:gray")
        b.legend(fontsize=8, loc="lower right")
        b.set_title("triaxial compression at p_m = 100 Pa")
    fig.tight_layout()
    path = os.path.join(out, "force-pdf.png")
    fig.savefig(path, dpi=120)
    return path


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/force-pdf"
    names = [n for n in KNOWN if os.path.exists(os.path.join(out, n, "analysis", "summary.json"))]
    if not names:  # run.sh wet alone: wet_report.py has reported it
        print(f"no dry case analysed under {out}: no dry summary")
        return
    iso_series = {}
    for iso in set(ISO_OF.values()):
        if os.path.exists(os.path.join(out, iso, "series.csv")):
            iso_series[iso] = read_columns(os.path.join(out, iso, "series.csv"))
    results, xs = {}, {}
    for n in names:
        results[n], xs[n] = report_case(out, n, iso_series)
    fig = figure(out, xs, results)
    for r in results.values():
        r["box"].pop("curve", None)
    json.dump({"paper": PAPER, "cases": results}, open(os.path.join(out, "summary.json"), "w"),
              indent=2)
    print(f"{'case':14s} {'beta (bulk)':>13s} {'beta (all)':>10s} {'f<<f>':>6s} {'P(0)':>5s} "
          f"{'z':>5s} {'z*':>5s} {'peak at':>7s} {'flat':>5s} {'alpha':>6s} {'phi':>6s} "
          f"{'run s':>6s}")
    for n, r in results.items():
        b, z, w = r["bulk"], r["bulk_coordination"], r["whole_sample_cli"]
        print(f"{n:14s} {b['beta_mle']:6.2f} +-{b['beta_mle_stderr']:4.2f} {w['beta_mle']:10.2f} "
              f"{b['fraction_below_mean']:6.2f} {b['p0']:5.2f} {z['z']:5.2f} "
              f"{z['z_without_rattlers']:5.2f} {b['weak_peak_at']:7.2f} "
              f"{b['weak_flatness_below_mean']:5.2f} "
              f"{b['weak_power_law_exponent'] if b['weak_power_law_exponent'] is not None else float('nan'):6.2f} "
              f"{r['box']['solid_fraction']:6.3f} "
              f"{r['run_seconds']:6.1f}")
        if "axial_strain" in r["box"] and "max_rel_error_sigma_xx_after_1pct" not in r["box"]:
            bx = r["box"]
            print(f"{'':14s} axial strain {100 * bx['axial_strain']:.2f} % at "
                  f"{bx['axial_strain_rate_per_s']:.3g} /s; q/p peak {bx['q_over_p_peak']:.3f} "
                  f"at {100 * bx['q_over_p_peak_at_strain']:.1f} %, end {bx['q_over_p_end']:.3f}")
        elif "axial_strain" in r["box"]:
            bx = r["box"]
            print(f"{'':14s} axial strain {100 * bx['axial_strain']:.2f} % at "
                  f"{bx['axial_strain_rate_per_s']:.3g} /s; q/p peak {bx['q_over_p_peak']:.3f} "
                  f"at {100 * bx['q_over_p_peak_at_strain']:.1f} %, end {bx['q_over_p_end']:.3f}; "
                  f"lateral stress within {100 * bx['max_rel_error_sigma_xx_after_1pct']:.1f} / "
                  f"{100 * bx['max_rel_error_sigma_yy_after_1pct']:.1f} % of p_m")
    print(f"paper: beta ~ {PAPER['beta']} (spheres), {PAPER['beta_polyhedra']} (polyhedra, S3), "
          f"fraction below the mean > {PAPER['fraction_below_mean_min']:.0%}")
    print("bulk: 2 <d> from the walls; all: sable analyze's own (every contact in analyses made "
          "before --region applied to force PDFs, the bulk since); z* without rattlers;")
    print("peak at: where the PDF is highest in bins of 0.1; flat: its lowest over highest bin "
          "below the mean; alpha: the weak forces' P ~ x^alpha over [0.01, 1)")
    print(f"wrote {os.path.join(out, 'summary.json')} and {fig}")


if __name__ == "__main__":
    main()
