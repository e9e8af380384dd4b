"""The balance checks of one rotating-cylinder run (issue 39's "Checks"), for analyze_run.py.

- power_balance: over the stationary window's snapshots (lab frame), the power the cylinder
  puts into the grains and the power the contacts dissipate (`sable analyze --only
  dissipation`, src/sable/analysis/dissipation.hpp), beside omega <M> from series.csv.
- weight_balance: at a level between the cylinder's top and the free surface, the weight of
  the grains above it against the integral of the coarse-grained sigma_zz over the horizontal
  plane there (sphere kernel R = 2 d, cells of d) plus what the walls carry of those grains
  and their momentum rate (`sable analyze --only fields,load-share`).
- stationarity: the turning-frame fields of the two halves of the stationary window, compared
  by the mean pressure in the bed within one L of the cylinder in its vertical plane.
- arch_tilt: how far the major stress axes above the cylinder lean towards it (Fig. 7).
Each returns a dict for summary.json (an "error" key when `sable analyze` failed).
"""
import csv
import json
import math
from pathlib import Path

import numpy as np


def read_table(path: Path) -> dict:
    """A CSV of `sable analyze` (fields.csv, fields_line.csv...) as {column: array}."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def plane_stress(grid: dict, i: int, ca: float, sa: float) -> np.ndarray:
    """Node i's stress in the vertical plane along (ca, sa, 0) and z: the 2 x 2 block (Pa),
    its off-diagonal the mean of the two shear components."""
    saa = (grid["sigma_xx_Pa"][i] * ca * ca + grid["sigma_yy_Pa"][i] * sa * sa +
           (grid["sigma_xy_Pa"][i] + grid["sigma_yx_Pa"][i]) * ca * sa)
    saz = 0.5 * ((grid["sigma_xz_Pa"][i] + grid["sigma_zx_Pa"][i]) * ca +
                 (grid["sigma_yz_Pa"][i] + grid["sigma_zy_Pa"][i]) * sa)
    return np.array([[saa, saz], [saz, grid["sigma_zz_Pa"][i]]])


def power_balance(analyze, snaps: list, out: Path, omega_torque_W: float) -> dict:
    if not analyze(snaps, out, ["--only", "dissipation"]):
        return {"error": "sable analyze --only dissipation failed (see analysis.log)"}
    p = json.loads((out / "summary.json").read_text())["dissipation"]
    cyl = p["walls"]["cylinder"]["mean_W"]
    diss = p["dissipation"]["mean_W"]
    return {
        "snapshots": p["snapshots"],
        "input_cylinder_W": cyl,
        "input_cylinder_sem_W": p["walls"]["cylinder"]["sem_W"],
        "input_all_walls_W": p["input_power"]["mean_W"],
        "omega_torque_series_W": omega_torque_W,
        "dissipation_W": diss,
        "dissipation_sem_W": p["dissipation"]["sem_W"],
        "damping_normal_W": p["damping_normal"]["mean_W"],
        "damping_tangential_W": p["damping_tangential"]["mean_W"],
        "sliding_W": p["sliding"]["mean_W"],
        "contact_power_W": p["contact_power"]["mean_W"],
        "energy_rate_W": p["energy_rate_W"],
        "input_over_dissipation": p["input_over_dissipation"],
        "omega_torque_over_dissipation": omega_torque_W / diss if diss else None,
    }


def weight_balance(analyze, snaps: list, out: Path, level: float, rc: float, d: float) -> dict:
    # One layer of cells of size ~d centred on the level, wide enough to hold the kernel's
    # reach beyond the container wall (R = 2 d): the plane integral is the sum of the nodes'
    # sigma_zz times the cell area.
    half = rc + 3.0 * d
    n = int(math.ceil(2.0 * half / d))
    region = f"{-half},{-half},{level - 0.5 * d}:{half},{half},{level + 0.5 * d}"
    if not analyze(snaps, out, ["--only", "fields,load-share", "--grid", f"{n}x{n}x1",
                                "--region", region, "--kernel", "sphere", "--width",
                                repr(2.0 * d), "--level", repr(level)]):
        return {"error": "sable analyze --only fields,load-share failed (see analysis.log)"}
    cell = (2.0 * half / n) ** 2
    integral = float(np.sum(read_table(out / "fields.csv")["sigma_zz_Pa"]) * cell)
    ls = json.loads((out / "summary.json").read_text())["load_share"]
    weight = ls["weight_N"]
    walls = ls["all_walls"]["force_N"]
    momentum = ls["momentum_rate"]["force_N"]
    fixed = ls["fixed_grains"]["force_N"]
    residual = weight - (integral + walls + fixed - momentum)
    return {
        "level_m": level, "snapshots": ls["snapshots"], "weight_N": weight,
        "sigma_zz_integral_N": integral, "exact_cut_N": ls["cut"]["force_N"],
        "walls_N": {k: v["force_N"] for k, v in ls["walls"].items()},
        "momentum_rate_N": momentum,
        "residual_over_weight": residual / weight if weight else None,
        "cg_over_exact_cut": integral / ls["cut"]["force_N"] if ls["cut"]["force_N"] else None,
    }


def stationarity(analyze, snaps: list, case: Path, frame: list, grid_args: list,
                 plane, zc: float, L: float) -> dict:
    """plane(grid) -> (keep, along): the nodes of the cylinder's vertical plane."""
    if len(snaps) < 4:
        return {"error": f"{len(snaps)} snapshots in the stationary window: too few to halve"}
    halves = (snaps[: len(snaps) // 2], snaps[len(snaps) // 2:])
    means = []
    for k, part in enumerate(halves):
        out = case / f"fields_stationary_half{k + 1}"
        if not analyze(part, out, ["--only", "fields", *grid_args, *frame]):
            return {"error": f"sable analyze --only fields on half {k + 1} failed"}
        grid = read_table(out / "fields.csv")
        keep, along = plane(grid)
        near = keep & (np.abs(along) <= L) & (np.abs(grid["z_m"] - zc) <= L) & (
            grid["volume_fraction"] > 0.3)
        means.append(float(np.mean(grid["pressure_Pa"][near])))
    return {"snapshots": [len(h) for h in halves], "pressure_near_cylinder_Pa": means,
            "relative_difference": abs(means[0] - means[1]) / (0.5 * (means[0] + means[1]))}


def arch_tilt(grid: dict, keep, along, ca: float, sa: float, zc: float, D: float, L: float,
              d: float) -> dict:
    """The paper's arches (its Fig. 7): over the nodes of the cylinder's vertical plane above
    it (from 2 d over its top to L above its axis, d < |along| <= L/2), the angle of the major
    axis of the in-plane stress block from the vertical, in degrees, signed positive when it
    leans towards the axis going up, as along the flanks of an arch over the cylinder: its
    mean, and the mean of its size."""
    z = grid["z_m"]
    sel = keep & (grid["pressure_Pa"] > 0) & (z > zc + D / 2 + 2 * d) & (z < zc + L) & (
        np.abs(along) <= 0.5 * L) & (np.abs(along) > d)
    out, size = [], []
    for i in np.flatnonzero(sel):
        vals, vecs = np.linalg.eigh(plane_stress(grid, i, ca, sa))
        va, vz = vecs[0, 1], vecs[1, 1]  # the major axis (the largest eigenvalue, last)
        if vz < 0:
            va, vz = -va, -vz
        angle = math.degrees(math.atan2(va, vz))
        out.append(-angle if along[i] > 0 else angle)
        size.append(abs(angle))
    if not out:
        return {"nodes": 0}
    return {"nodes": len(out), "arch_tilt_deg": float(np.mean(out)),
            "tilt_size_deg": float(np.mean(size))}
