#!/usr/bin/python3
"""Drag, torque balance and turning-frame fields of one run of the rotating cylinder
(examples/rotating-cylinder/run.sh; docs/examples.md, "Rotating cylinder").

    /usr/bin/python3 examples/rotating-cylinder/analyze_run.py CASE [--sable BIN]
        [--stationary-from TURNS]

CASE holds scenario.toml and scenario.json (make_scenario.py), run.log and run/ (the run's
outputs). Writes into CASE:
  drag_halfturns.csv  per half-turn: rows, mean torque M on the cylinder, its sd, drag 4 M / L
  fig2_drag_vs_turns.png   drag / (rho g D L^2) against turns (the paper's Fig. 2)
  fig5_isobars.png    pressure in the cylinder's vertical plane, turning frame, first half-turn
                      and stationary window (Fig. 5 a, b)
  fig6_axis.png       pressure and volume fraction along the vertical axis (Figs. 5c, 6a)
  fig7_ellipses.png   stress ellipses sigma.n / P in the cylinder's plane (Fig. 7)
  summary.json        drags, torque balance, input power, depth measured after the pour,
                      pressure minimum above the cylinder, the balances of checks.py
                      (power, weight, stationarity), settings
  fields_first/, fields_stationary/, axis_first/, axis_stationary/, surface/, dissipation/,
  weight/, fields_stationary_half1/, fields_stationary_half2/  (sable analyze)
The drag is computed here from series.csv, and again by `sable analyze --only drag` (a check);
`sable analyze --only load-share` at the cylinder's top gives the container wall's share of the
weight above it; their summaries are copied in.
"""
import argparse
import csv
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import checks  # noqa: E402

G = 9.81


def fail(message: str) -> None:
    print(f"analyze_run.py: {message}", file=sys.stderr)
    sys.exit(1)


def read_series(path: Path) -> dict:
    if not path.is_file():
        fail(f"{path}: missing (did the run start?)")
    data = np.genfromtxt(path, delimiter=",", names=True)
    if data.size < 2:
        fail(f"{path}: fewer than two rows")
    return data


def turn_start(log: Path) -> float:
    """Time at which the stage 'turn' began (the first such line: a resumed run repeats none)."""
    if not log.is_file():
        fail(f"{log}: missing")
    m = re.search(r"stage \d+ 'turn' begins at step \d+ \(t = ([0-9.eE+-]+) s", log.read_text())
    if not m:
        fail(f"{log}: no line \"stage 2 'turn' begins\": the pour has not ended")
    return float(m.group(1))


def snapshots(run: Path) -> list:
    """(time, path) of the run's snapshots, by step."""
    out = []
    for p in (run / "snapshots").glob("*.h5"):
        m = re.search(r"step_(\d+)", p.name)
        if m:
            out.append((int(m.group(1)), p))
    return sorted(out)


def sable_analyze(sable: str, snaps: list, out: Path, args: list) -> bool:
    cmd = [sable, "analyze", *[str(p) for p in snaps], "--out", str(out), *args]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        print(f"analyze_run.py: {' '.join(cmd[:2])} ... {' '.join(args)}: exit {r.returncode}: "
              f"{r.stderr.strip()[-400:]}", file=sys.stderr)
    return r.returncode == 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("case")
    ap.add_argument("--sable", default="build/release/bin/sable")
    ap.add_argument("--stationary-from", type=float,
                    help="turns after which the drag is stationary (default: the last turn)")
    a = ap.parse_args()
    case = Path(a.case)
    settings_path = case / "scenario.json"
    if not settings_path.is_file():
        fail(f"{settings_path}: missing (make_scenario.py writes it)")
    s = json.loads(settings_path.read_text())
    run = case / "run"
    data = read_series(run / "series.csv")
    t0 = turn_start(case / "run.log")
    omega, L, D, rho = s["omega_rad_s"], s["L_m"], s["D_m"], s["rho_kg_m3"]
    scale = rho * G * D * L * L  # the paper's drag unit D L rho g L (rho: the grains' density)
    t = data["time_s"]
    m_cyl = data["wall_cylinder_tz_Nm"]
    m_walls = data["wall_container_tz_Nm"] + data["wall_floor_tz_Nm"]
    turns = omega * (t - t0) / (2.0 * math.pi)
    on = turns > 0.0
    if on.sum() < 4:
        fail(f"{run / 'series.csv'}: fewer than 4 rows after the turning began")
    total = float(turns[on][-1])
    # The grains resist the turning: M < 0 for omega > 0; the drag is its size.
    drag = -4.0 * m_cyl / L

    halves = []
    for k in range(int(math.floor(2.0 * total + 1e-9))):
        sel = on & (turns > 0.5 * k) & (turns <= 0.5 * (k + 1))
        if sel.sum() == 0:
            continue
        halves.append({"half_turn": k, "t_start_s": t0 + k * math.pi / omega,
                       "t_end_s": t0 + (k + 1) * math.pi / omega, "rows": int(sel.sum()),
                       "torque_Nm": float(np.mean(m_cyl[sel])),
                       "torque_sd_Nm": float(np.std(m_cyl[sel])),
                       "drag_N": float(np.mean(drag[sel]))})
    with open(case / "drag_halfturns.csv", "w", newline="") as f:
        w = csv.DictWriter(f, lineterminator="\n",
                           fieldnames=["half_turn", "t_start_s", "t_end_s", "rows", "torque_Nm",
                                       "torque_sd_Nm", "drag_N"])
        w.writeheader()
        w.writerows(halves)
    stat_from = a.stationary_from if a.stationary_from is not None else max(0.5, total - 1.0)
    if a.stationary_from is not None and stat_from >= total:
        fail(f"--stationary-from {stat_from} is not before the run's last turn {total:.3f}")
    first = on & (turns <= 0.5)
    # A run shorter than half a turn (the CI test's) has no stationary window: its balance
    # and power are taken over all the turning rows.
    stat = on & (turns > stat_from) if stat_from < total else on
    first_drag = float(np.mean(drag[first]))
    stat_drag = float(np.mean(drag[stat])) if stat_from < total else math.nan
    m_mean = float(np.mean(m_cyl[stat]))
    w_mean = float(np.mean(m_walls[stat]))
    # Two halves of the stationary window: how stationary it is.
    stat_idx = np.flatnonzero(stat)
    half_a, half_b = stat_idx[: len(stat_idx) // 2], stat_idx[len(stat_idx) // 2:]

    summary = {
        "settings": s,
        "turn_start_s": t0,
        "turns_run": total,
        "drag_first_half_turn_N": first_drag,
        "drag_stationary_N": stat_drag,
        "stationary_window_turns": [stat_from, total] if stat_from < total else None,
        "drag_first_half_turn_over_rho_g_D_L2": first_drag / scale,
        "drag_stationary_over_rho_g_D_L2": stat_drag / scale,
        "drag_stationary_halves_N": [float(np.mean(drag[half_a])), float(np.mean(drag[half_b]))]
        if stat_from < total else None,
        "torque_cylinder_Nm": m_mean,
        "torque_container_and_floor_Nm": w_mean,
        # Without the grains' angular momentum (series.csv has none): over a window of whole
        # turns in a stationary state its change averages out; the CI test closes the balance
        # exactly with it (tests/validation/test_rotating_cylinder.cpp).
        "torque_balance_residual_over_cylinder": (m_mean + w_mean) / abs(m_mean),
        "input_power_W": -omega * m_mean,
        "drag_unit_rho_g_D_L2_N": scale,
    }

    # Depth measured after the pour: the free surface where the volume fraction along a
    # vertical line halfway to the wall (off the cylinder) falls to half its bulk value.
    pour_end = run / "snapshots" / "end_of_stage_1.h5"
    rc, hc, zc = s["container_radius_m"], s["container_height_m"], s["cylinder_center_z_m"]
    if pour_end.is_file() and sable_analyze(
            a.sable, [pour_end], case / "surface",
            ["--only", "fields", "--line", f"0,{0.5 * rc},0:0,{0.5 * rc},{1.3 * hc}:400"]):
        prof = checks.read_table(case / "surface" / "fields_line.csv")
        phi = prof["volume_fraction"]
        bulk = float(np.median(phi[(prof["z_m"] > 0.2 * hc) & (prof["z_m"] < 0.8 * hc)]))
        above = np.flatnonzero(phi >= 0.5 * bulk)
        surface = float(prof["z_m"][above[-1]])
        summary.update({"surface_m": surface, "solid_fraction_bulk": bulk,
                        "h_measured_m": surface - zc, "h_over_L_measured": (surface - zc) / L,
                        "inertial_number_measured_depth":
                            omega * s["d_m"] / math.sqrt(bulk * G * (surface - zc))})
    h_over_l = summary.get("h_over_L_measured", s["h_over_L_planned"])

    # The same drag per half-turn by `sable analyze --only drag` (docs/analysis.md), from the
    # turning's start: a check on this script's own numbers.
    snaps = snapshots(run)
    turning = [p for step, p in snaps if step * s["dt_s"] > t0 + 0.5 * s["dt_s"]]
    if turning and sable_analyze(
            a.sable, turning, case / "drag_sable",
            ["--only", "drag", "--drag-wall", "cylinder", "--omega", repr(omega),
             "--drag-axis", "0,0,1", "--drag-length", repr(L), "--series",
             str(run / "series.csv"), "--turn-start", repr(t0),
             "--stationary-from", repr(stat_from)]):
        summary["sable_analyze_drag"] = json.loads((case / "drag_sable" / "summary.json").read_text())
    else:
        summary["sable_analyze_drag"] = "sable analyze --only drag failed (see analysis.log)"

    # The share of the weight above the cylinder's top that the container wall carries
    # (`sable analyze --only load-share`), over the stationary window.
    stat_snaps = [p for step, p in snaps
                  if omega * (step * s["dt_s"] - t0) / (2 * math.pi) > min(stat_from, total)]
    if stat_snaps and sable_analyze(a.sable, stat_snaps, case / "load_share",
                                    ["--only", "load-share", "--level", repr(zc + D / 2)]):
        summary["sable_analyze_load_share"] = json.loads(
            (case / "load_share" / "summary.json").read_text())
    else:
        summary["sable_analyze_load_share"] = "sable analyze --only load-share failed (see analysis.log)"

    # The balances of the stationary window (checks.py): input power against dissipation, and
    # the weight above a level midway between the cylinder's top and the surface against the
    # coarse-grained sigma_zz there.
    def analyze(snaps_, out_, args_):
        return sable_analyze(a.sable, snaps_, out_, args_)

    d = s["d_m"]
    if stat_snaps and stat_from < total:
        summary["power_balance"] = checks.power_balance(analyze, stat_snaps, case / "dissipation",
                                                        -omega * m_mean)
        level = 0.5 * (zc + D / 2 + summary.get("surface_m", hc))
        summary["weight_balance"] = checks.weight_balance(analyze, stat_snaps, case / "weight",
                                                          level, rc, d)

    # Figure 2: drag against turns.
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(turns[on], drag[on] / scale, lw=0.6, color="C0", label=f"h/L = {h_over_l:.2f}")
    for hrow in halves:
        ax.hlines(hrow["drag_N"] / scale, 0.5 * hrow["half_turn"], 0.5 * (hrow["half_turn"] + 1),
                  color="k", lw=1.5)
    ax.set_xlabel("turns")
    ax.set_ylabel(r"$F_{drag} / (\rho g D L^2)$")
    ax.set_title(f"E* = {s['E_star']:.3g}, L = {s['L_over_d']:g} d (black: half-turn means)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(case / "fig2_drag_vs_turns.png", dpi=120)
    plt.close(fig)

    # Turning-frame fields: the first half-turn and the stationary window. The frame of
    # `sable analyze --frame` coincides with the lab's at t = 0, so the cylinder (along x when
    # the turning begins) lies at the angle -omega t0 in it: the cylinder's vertical plane is
    # sampled there from a 3D grid.
    def window(lo_turns, hi_turns):
        return [p for step, p in snaps
                if lo_turns < omega * (step * s["dt_s"] - t0) / (2 * math.pi) <= hi_turns + 1e-9]

    # Up to the measured surface (the pour packs looser than planned near the walls, so the
    # bed stands a few d above the container's planned height), at least to that height.
    top = max(hc, summary.get("surface_m", hc) + 2 * d)
    n_xy = max(4, round(2 * rc / d))
    n_z = max(8, round(top / d))
    region = f"{-rc},{-rc},0:{rc},{rc},{top}"
    frame = ["--frame", "0,0,0:0,0,1", "--omega", repr(omega), "--kernel", "sphere",
             "--width", repr(2 * d)]
    fields = {}
    windows = {"first": (0.0, 0.5)}
    if stat_from < total:
        windows["stationary"] = (stat_from, total)
    for name, (lo, hi) in windows.items():
        snaps_w = window(lo, hi)
        if not snaps_w:
            continue
        ok = sable_analyze(a.sable, snaps_w, case / f"fields_{name}",
                           ["--only", "fields", "--grid", f"{n_xy}x{n_xy}x{n_z}", "--region",
                            region, *frame])
        ok = ok and sable_analyze(a.sable, snaps_w, case / f"axis_{name}",
                                  ["--only", "fields", "--line", f"0,0,0:0,0,{top}:{4 * n_z}",
                                   *frame])
        if ok:
            fields[name] = (checks.read_table(case / f"fields_{name}" / "fields.csv"),
                            checks.read_table(case / f"axis_{name}" / "fields_line.csv"),
                            len(snaps_w))
    summary["field_windows_snapshots"] = {k: v[2] for k, v in fields.items()}
    alpha = -omega * t0
    ca, sa = math.cos(alpha), math.sin(alpha)

    def plane(grid):
        """The grid's nodes nearest the cylinder's vertical plane: (s, z, tensor rows...)."""
        x, y = grid["x_m"], grid["y_m"]
        along = x * ca + y * sa
        across = -x * sa + y * ca
        keep = (np.abs(across) <= 0.5 * d + 1e-12) & (np.hypot(x, y) < rc - d)
        return keep, along

    for name, (grid, _, _) in fields.items():
        keep, along = plane(grid)
        summary[f"arch_tilt_{name}"] = checks.arch_tilt(grid, keep, along, ca, sa, zc, D, L, d)
    if "stationary" in windows:
        summary["stationarity"] = checks.stationarity(
            analyze, window(*windows["stationary"]), case, frame,
            ["--grid", f"{n_xy}x{n_xy}x{n_z}", "--region", region], plane, zc, L)

    if fields:
        fig, axes = plt.subplots(1, len(fields), figsize=(5 * len(fields), 7), squeeze=False)
        pmax = max(float(np.percentile(g["pressure_Pa"], 99)) for g, _, _ in fields.values())
        for ax, (name, (grid, _, n)) in zip(axes[0], fields.items()):
            keep, along = plane(grid)
            sc = ax.tricontourf(along[keep] / L, grid["z_m"][keep] / L, grid["pressure_Pa"][keep],
                                levels=np.linspace(0, pmax, 16), cmap="viridis", extend="max")
            ax.tricontour(along[keep] / L, grid["z_m"][keep] / L, grid["pressure_Pa"][keep],
                          levels=np.linspace(0, pmax, 16), colors="k", linewidths=0.4)
            ax.add_patch(plt.Rectangle((-0.5, (zc - D / 2) / L), 1.0, D / L, color="r"))
            ax.set_aspect("equal")
            ax.set_xlabel("distance along the cylinder / L")
            ax.set_ylabel("z / L")
            ax.set_title(f"{name} ({n} snapshots)")
            fig.colorbar(sc, ax=ax, label="pressure (Pa)")
        fig.suptitle("isobars in the cylinder's vertical plane, turning frame (Fig. 5a, b)")
        fig.tight_layout()
        fig.savefig(case / "fig5_isobars.png", dpi=120)
        plt.close(fig)

        fig, (axp, axf) = plt.subplots(1, 2, figsize=(9, 6), sharey=True)
        for name, (_, line, _) in fields.items():
            axp.plot(line["pressure_Pa"], line["z_m"] / L, label=name)
            axf.plot(line["volume_fraction"], line["z_m"] / L, label=name)
        for ax in (axp, axf):
            ax.axhline(zc / L, color="r", lw=0.8)
            ax.legend(fontsize=8)
        axp.set_xlabel("pressure on the axis (Pa)")
        axf.set_xlabel("volume fraction on the axis")
        axf.set_xlim(0.45, 0.7)
        axp.set_ylabel("z / L (red: the cylinder)")
        fig.tight_layout()
        fig.savefig(case / "fig6_axis.png", dpi=120)
        plt.close(fig)

        # Pressure minimum above the cylinder (Fig. 6b) and the change of the volume fraction
        # on the axis between the two windows, over the bed above the cylinder.
        surf = summary.get("surface_m", hc)
        for name, (_, line, _) in fields.items():
            z = line["z_m"]
            sel = (z > zc + D / 2 + 2 * d) & (z < surf - 2 * d)
            # The paper's z_drop: a local minimum of the pressure going up from the cylinder,
            # the lowest of a window of +-2 d, with the hydrostatic rise above it at least 5 %
            # higher; none (null) where the pressure only falls towards the surface.
            p_sel, z_sel = line["pressure_Pa"][sel], z[sel]
            half = max(1, int(round(2 * d / (z[1] - z[0]))))
            drops = [i for i in range(len(p_sel))
                     if p_sel[i] == p_sel[max(0, i - half):i + half + 1].min()
                     and p_sel[i + 1:].size and p_sel[i + 1:].max() > 1.05 * p_sel[i]]
            if drops:
                k = min(drops, key=lambda i: p_sel[i])
                summary[f"pressure_min_above_cylinder_{name}_over_L"] = float(
                    (z_sel[k] - zc) / L)
            else:
                summary[f"pressure_min_above_cylinder_{name}_over_L"] = None
            if sel.sum() > 2:
                summary[f"volume_fraction_axis_above_{name}"] = float(
                    np.mean(line["volume_fraction"][sel]))
        if "first" in fields and "stationary" in fields:
            summary["volume_fraction_axis_change"] = (summary.get(
                "volume_fraction_axis_above_stationary", math.nan) - summary.get(
                "volume_fraction_axis_above_first", math.nan))

        # Stress ellipses: the in-plane block of sigma / P (Guillard eq. 5), coloured by P.
        fig, axes = plt.subplots(1, len(fields), figsize=(5 * len(fields), 7), squeeze=False)
        for ax, (name, (grid, _, _)) in zip(axes[0], fields.items()):
            keep, along = plane(grid)
            keep &= grid["pressure_Pa"] > 0
            idx = np.flatnonzero(keep)
            # Every second node along the plane and every third up it, by rank.
            col = np.unique(np.round(along[idx] / d, 3), return_inverse=True)[1]
            row = np.unique(grid["z_m"][idx], return_inverse=True)[1]
            idx = idx[(col % 2 == 0) & (row % 3 == 0)]
            norm = matplotlib.colors.Normalize(0, pmax)
            for i in idx:
                m2 = checks.plane_stress(grid, i, ca, sa) / grid["pressure_Pa"][i]
                vals, vecs = np.linalg.eigh(m2)
                vals = np.clip(vals, 0.05, None)
                size = 1.6 * d / L / max(vals.max(), 1.0)
                ang = math.degrees(math.atan2(vecs[1, 1], vecs[0, 1]))
                ax.add_patch(matplotlib.patches.Ellipse(
                    (along[i] / L, grid["z_m"][i] / L), size * vals[1], size * vals[0], angle=ang,
                    color=plt.cm.viridis(norm(grid["pressure_Pa"][i]))))
            ax.add_patch(plt.Rectangle((-0.5, (zc - D / 2) / L), 1.0, D / L, color="r"))
            ax.set_xlim(-rc / L, rc / L)
            ax.set_ylim(0, top / L)
            ax.set_aspect("equal")
            ax.set_title(f"{name}: sigma.n / P in the plane, colour P")
            ax.set_xlabel("distance along the cylinder / L")
            ax.set_ylabel("z / L")
        fig.tight_layout()
        fig.savefig(case / "fig7_ellipses.png", dpi=120)
        plt.close(fig)

    for key, value in summary.items():  # JSON has no NaN: a missing value is null
        if isinstance(value, float) and not math.isfinite(value):
            summary[key] = None
    (case / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(json.dumps({k: v for k, v in summary.items() if k != "settings"}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
