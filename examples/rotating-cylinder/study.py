#!/usr/bin/python3
"""The rotating-cylinder study across cases (examples/rotating-cylinder/run.sh).

    /usr/bin/python3 examples/rotating-cylinder/study.py ROOT

reads ROOT/*/summary.json (analyze_run.py) and writes ROOT/study.json (one row per case: E*,
h/L measured, first-half-turn and stationary drag / (rho g D L^2), pressure minimum above the
cylinder / L), ROOT/fig3_drag_vs_depth.png (the paper's Figs. 2-4: both drags against h/L, one
colour per stiffness), ROOT/fig6a_axis_pressure.png (the stationary pressure on the vertical
axis of every case, one panel per stiffness, a dot at each cylinder) and
ROOT/fig6b_pressure_min.png (distance of the pressure minimum above the cylinder against h/L).
Cases without a summary are listed as pending. study.json's "checks" holds the issue's
comparisons across cases, where the cases they need are there: the first-half-turn drag of the
two stiffnesses at each planned depth, stationary against first half-turn, the stiff
stationary drag over h/L >= 2, the soft one's growth with depth, and 128 against 32 facets.
"""
import csv
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def study_checks(rows: list) -> dict:
    """The issue's comparisons across cases (drags in units of rho g D L^2)."""
    plain = [r for r in rows if r["facets"] == 32]
    stiffnesses = sorted({r["E_star"] for r in plain})
    out = {"stationary_below_first": {r["case"]: r["stationary"] < r["first"] for r in rows
                                      if r["stationary"] is not None}}
    if len(stiffnesses) >= 2:
        soft, stiff = stiffnesses[0], stiffnesses[-1]
        pairs = {}
        for r in plain:
            if r["E_star"] != soft:
                continue
            other = [q for q in plain if q["E_star"] == stiff
                     and q["h_over_L_planned"] == r["h_over_L_planned"]]
            if other:
                pairs[f"h/L = {r['h_over_L_planned']:g}"] = other[0]["first"] / r["first"] - 1.0
        out["first_half_turn_stiff_over_soft_minus_1"] = pairs
    for e in stiffnesses:
        deep = [r for r in plain if r["E_star"] == e and r["h_over_L"] >= 2.0
                and r["stationary"] is not None]
        if len(deep) >= 2:
            values = [r["stationary"] for r in deep]
            out[f"stationary_spread_h_ge_2_E*={e:.3g}"] = (max(values) - min(values)) / (
                sum(values) / len(values))
    for r in rows:
        if r["facets"] == 32:
            continue
        twin = [q for q in plain if q["E_star"] == r["E_star"]
                and q["h_over_L_planned"] == r["h_over_L_planned"]]
        if twin and twin[0]["stationary"] and r["stationary"]:
            out[f"{r['case']}_stationary_over_32_facets_minus_1"] = (
                r["stationary"] / twin[0]["stationary"] - 1.0)
    return out


def main() -> int:
    if len(sys.argv) != 2:
        print("usage: study.py ROOT", file=sys.stderr)
        return 2
    root = Path(sys.argv[1])
    rows, pending = [], []
    for case in sorted(p for p in root.iterdir() if p.is_dir()):
        f = case / "summary.json"
        if not f.is_file():
            pending.append(case.name)
            continue
        s = json.loads(f.read_text())
        rows.append({
            "case": case.name, "E_star": s["settings"]["E_star"],
            "facets": s["settings"].get("facets", 32),
            "h_over_L_planned": s["settings"]["h_over_L_planned"],
            "h_over_L": s.get("h_over_L_measured", s["settings"]["h_over_L_planned"]),
            "turns": s["turns_run"],
            "first": s["drag_first_half_turn_over_rho_g_D_L2"],
            "stationary": s["drag_stationary_over_rho_g_D_L2"],
            "pressure_min_over_L": s.get("pressure_min_above_cylinder_stationary_over_L"),
            "torque_balance_residual": s["torque_balance_residual_over_cylinder"],
        })
    checks = study_checks(rows)
    (root / "study.json").write_text(json.dumps({"cases": rows, "pending": pending,
                                                 "checks": checks}, indent=2) + "\n")
    if not rows:
        print(f"study.py: no case of {root} has a summary.json yet", file=sys.stderr)
        return 0
    fig, ax = plt.subplots(figsize=(6, 4))
    for k, (e, nf) in enumerate(sorted({(r["E_star"], r["facets"]) for r in rows})):
        sel = sorted((r for r in rows if (r["E_star"], r["facets"]) == (e, nf)),
                     key=lambda r: r["h_over_L"])
        x = [r["h_over_L"] for r in sel]
        tag = f"E* = {e:.2g}" + (f", {nf} facets" if nf != 32 else "")
        ax.plot(x, [r["first"] for r in sel], "o--", color=f"C{k}", mfc="none",
                label=f"first half-turn, {tag}")
        ax.plot(x, [r["stationary"] for r in sel], "s-", color=f"C{k}", label=f"stationary, {tag}")
    ax.set_xlabel("h / L (measured after the pour)")
    ax.set_ylabel(r"$F_{drag} / (\rho g D L^2)$")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(root / "fig3_drag_vs_depth.png", dpi=120)
    plt.close(fig)
    stiffnesses = sorted({r["E_star"] for r in rows})
    fig, axes = plt.subplots(1, len(stiffnesses), figsize=(4.5 * len(stiffnesses), 6),
                             squeeze=False, sharey=True)
    for ax, e in zip(axes[0], stiffnesses):
        for r in sorted((r for r in rows if r["E_star"] == e and r["facets"] == 32),
                        key=lambda r: r["h_over_L"]):
            line = root / r["case"] / "axis_stationary" / "fields_line.csv"
            if not line.is_file():
                continue
            with open(line) as f:
                prof = list(csv.DictReader(f))
            settings = json.loads((root / r["case"] / "scenario.json").read_text())
            length, zc = settings["L_m"], settings["cylinder_center_z_m"]
            z = [float(p["z_m"]) / length for p in prof]
            pressure = [float(p["pressure_Pa"]) for p in prof]
            (curve,) = ax.plot(pressure, z, lw=0.8, label=f"h/L = {r['h_over_L']:.2f}")
            k = min(range(len(z)), key=lambda i: abs(z[i] - zc / length))
            ax.plot([pressure[k]], [z[k]], "o", color=curve.get_color())
        ax.set_title(f"E* = {e:.2g}, stationary")
        ax.set_xlabel("pressure on the axis (Pa)")
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel("z / L")
    fig.tight_layout()
    fig.savefig(root / "fig6a_axis_pressure.png", dpi=120)
    plt.close(fig)
    have = [r for r in rows if r["pressure_min_over_L"] is not None]
    if have:
        fig, ax = plt.subplots(figsize=(5, 4))
        ax.plot([r["h_over_L"] for r in have], [r["pressure_min_over_L"] for r in have], "o")
        ax.axhspan(0.7, 1.3, color="grey", alpha=0.2, label="0.7-1.3 L (issue's check)")
        ax.set_xlabel("h / L")
        ax.set_ylabel(r"$(z_{drop} - z_{cyl}) / L$, stationary")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(root / "fig6b_pressure_min.png", dpi=120)
        plt.close(fig)
    print(json.dumps({"cases": rows, "pending": pending}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
