#!/usr/bin/python3
"""The checks of scripts/run-examples.sh: each example's key figures against bounds, each bound
with its reason (a physical law, an analytic solution, or the documented value with its
statistical spread, docs/examples.md).

Usage: check_examples.py ROOT   (the output root run-examples.sh wrote; exit 1 on a failure)

The runs are deterministic: the same code gives the same numbers to the bit, so a statistical
bound only matters for a change of the code that alters round-off (another trajectory of the
same physics); bounds of that kind are the documented value +- about four of its standard
errors. Debian's python3 and numpy only.
"""
import csv
import json
import math
import os
import sys
import tomllib

import numpy as np

G = 9.81
failures = []


def check(example, what, value, lo, hi, reason):
    ok = value is not None and lo <= value <= hi
    print(f"{'ok  ' if ok else 'FAIL'} {example}: {what} = {value:.6g} in [{lo:.6g}, {hi:.6g}]"
          if value is not None else f"FAIL {example}: {what} missing", f"-- {reason}")
    if not ok:
        failures.append(f"{example}: {what}")


def load(path):
    with open(path) as f:
        return json.load(f)


def columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    body = np.array(rows[1:], dtype=float)
    return {name: body[:, k] for k, name in enumerate(rows[0])}


def silo(root):
    s = load(os.path.join(root, "silo-janssen", "summary.json"))
    mu_w = 0.25  # the walls' friction in both scenarios
    for case in ("cd-2d-rolling", "cd-2d"):
        c = s[case]
        check(case, "floor + wall friction / weight at rest, before the descent",
              c["before"]["support_over_weight"], 0.99, 1.01,
              "static balance; CD meets it to 1e-5 here, docs/examples.md")
        check(case, "wall shear / normal force during the descent",
              c["relax"]["wall_shear_over_normal"], 0.15, mu_w * 1.001,
              "at most mu_w = 0.25 (Coulomb, to the solver's tolerance); at least 0.15: the "
              "descent mobilises the wall friction (documented 0.245 with rolling resistance, "
              "0.197 without; below 0.08 before the descent)")
        check(case, "Janssen R^2 during the descent", c["janssen"]["r2"], 0.9, 1.0,
              "the validation tests' bound, SiloJanssen.*; documented 0.98 and 0.92")
    check("cd-2d-rolling", "side-wall contacts on the Coulomb cone during the descent",
          s["cd-2d-rolling"]["relax"]["wall_fraction_on_cone"], 0.9, 1.0,
          "the paper's Figure 7a, most wall contacts polarized; documented 97.9 %")
    k = s["cd-2d-rolling"]["janssen"]
    check("cd-2d-rolling", "Janssen K (mu_w = 0.25)", k["K"], 0.81 - 0.16, 0.81 + 0.16,
          "documented 0.81 +- 0.04 over the eight seeds: four standard errors")


def force_pdf(root):
    s = load(os.path.join(root, "force-pdf", "summary.json"))["cases"]
    documented = {"iso-dem": (1.29, 0.59), "triaxial-dem": (1.20, 0.61)}
    for case, (beta, below) in documented.items():
        b = s[case]["bulk"]
        check(case, "fraction of the bulk normal forces below the mean",
              b["fraction_below_mean"], below - 0.045, below + 0.045,
              f"Richefeu et al. (2009): over 0.6; documented {below} over ~2,000 contacts "
              "(standard error 0.011): four standard errors")
        check(case, "exponent beta of the force tail", b["beta_mle"],
              beta - 4 * b["beta_mle_stderr"], beta + 4 * b["beta_mle_stderr"],
              f"documented {beta}, the paper's ~1.4: four of its standard errors")
        check(case, "P(0), the density of forces below 0.1 <f>", b["p0"], 0.05, 10.0,
              "finite and non-zero at zero force, the paper's robust feature")
    box = s["triaxial-dem"]["box"]
    check("triaxial-dem", "axial strain reached", box["axial_strain"], 0.095, 0.105,
          "the scenario compresses to 10 % (docs/examples.md: 10.1 %)")
    for k in ("sigma_xx", "sigma_yy"):
        check("triaxial-dem", f"largest deviation of {k} from p_m after 1 % strain",
              box[f"max_rel_error_{k}_after_1pct"], 0.0, 0.06,
              "the lateral walls are servoed to p_m = 100 Pa; documented within 4.3 %")


def force_pdf_wet(root):
    s = load(os.path.join(root, "force-pdf", "wet", "summary.json"))
    for label in ("0pa", "100pa"):
        w = s[label]
        check(f"wet {label}", "largest tensile force / f0", w["max_tensile_over_f0"], 0.5, 1.0,
              "a bridge pulls at most kappa sqrt(R_i R_j) <= kappa R_max = f0")
        check(f"wet {label}", "z = compressive + tensile bonds",
              w["z"] - w["z_compressive"] - w["z_tensile"], -1e-9, 1e-9, "bookkeeping")
    check("wet 0pa", "mean normal force / f0", s["0pa"]["mean_fn_over_f0"], -0.15, 0.15,
          "unconfined: the bonds' tension balances the contacts' compression (documented -0.04)")
    check("wet 100pa", "mean normal force / f0", s["100pa"]["mean_fn_over_f0"], 0.1, 0.6,
          "confined at 100 Pa: compression dominates (documented 0.29)")


def disk_weight(scenario):
    """m g of one disk of the cd-arrays scenario (2D: a disk of the scenario's thickness)."""
    with open(scenario, "rb") as f:
        sc = tomllib.load(f)
    r = sc["grains"][0]["radius"]
    return sc["material"][0]["density"] * math.pi * r * r * sc["simulation"]["thickness"] * G


def wall_forces(series, axis):
    """The last row's force on each wall along axis (the force the grains exert on it)."""
    c = columns(series)
    return {k: v[-1] for k, v in c.items() if k.startswith("wall_") and k.endswith(f"_f{axis}_N")}


def cd_arrays(root):
    here = os.path.join(root, "cd-arrays")
    for name in ("cannonball", "rectangular", "cannonball-friction", "rectangular-friction",
                 "triangular", "triangular-friction"):
        mg = disk_weight(os.path.join("examples", "cd-arrays", name + ".toml"))
        run = os.path.join(here, name)
        fy = wall_forces(os.path.join(run, "series.csv"), "y")
        grains = 3 if name.startswith("cannonball") else 48 if "rectangular" in name else 45
        check(name, "walls' vertical force / weight of the disks", -sum(fy.values()) /
              (grains * mg), 1 - 1e-6, 1 + 1e-6,
              "static balance at rest; the NLGS tolerance is 1e-10")
    # Frictionless: the forces are unique, and known (tests/validation/test_cd_statics.cpp).
    mg = disk_weight(os.path.join("examples", "cd-arrays", "cannonball.toml"))
    c = columns(os.path.join(here, "cannonball", "analysis", "contacts.csv"))
    fn = np.sort(c["fn_N"][c["wall"] == 0])[::-1]
    c30, t30 = math.cos(math.pi / 6), math.tan(math.pi / 6)
    for k in (0, 1):
        check("cannonball", f"upper contact {k + 1}: fn / (W / (2 cos 30))",
              fn[k] / (mg / (2 * c30)), 1 - 1e-6, 1 + 1e-6,
              "the upper disk's weight W split along its two contacts at 30 degrees")
    check("cannonball", "the lower disks' mutual force / W", fn[2:].sum() / mg if len(fn) > 2
          else 0.0, 0.0, 1e-9, "1 nm apart: they never touch")
    fx = wall_forces(os.path.join(here, "cannonball", "series.csv"), "x")
    for wall, f in fx.items():
        if "xlo" in wall or "xhi" in wall:
            check("cannonball", f"{wall}: |f| / (W tan 30 / 2)", abs(f) / (mg * t30 / 2),
                  1 - 1e-6, 1 + 1e-6, "the upper contacts' horizontal thrust, held by the walls")
    mg = disk_weight(os.path.join("examples", "cd-arrays", "rectangular.toml"))
    c = columns(os.path.join(here, "rectangular", "analysis", "contacts.csv"))
    fn = np.sort(c["fn_N"][(c["wall"] == 0) & (c["fn_N"] > 1e-9 * mg)])
    want = np.sort(np.repeat(np.arange(1, 6), 8)) * mg  # 8 columns, 1 to 5 disks above
    check("rectangular", "force-carrying contacts between disks", len(fn), 40, 40,
          "the 40 vertical contacts of 8 columns of 6 disks; the horizontal ones carry nothing")
    if len(fn) == 40:
        check("rectangular", "largest |fn - k m g| / m g over the columns' contacts",
              float(np.max(np.abs(fn - want)) / mg), 0.0, 1e-6,
              "each vertical contact carries the k disks above it")


def pour(root):
    run = os.path.join(root, "pour", "run")
    log = open(os.path.join(root, "pour.log")).read()
    check("pour (2,000 spheres)", "stages that hit max_steps before equilibrium",
          log.count("reached max_steps"), 0, 0,
          "the bed settles (kinetic energy below 1e-8 J) within the 150,000-step cap")
    with open(os.path.join(root, "pour", "pour-2000.toml"), "rb") as f:
        sc = tomllib.load(f)
    r = sc["grains"][0]["radius"]
    weight = sc["grains"][0]["count"] * sc["material"][0]["density"] * 4 / 3 * math.pi * r ** 3 * G
    fz = wall_forces(os.path.join(run, "series.csv"), "z")
    check("pour (2,000 spheres)", "walls' vertical force / weight, end of the dense phase",
          -sum(fz.values()) / weight, 0.99, 1.01,
          "a bed at rest: the floor and the walls' friction carry its weight")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = sys.argv[1]
    for name, f in (("silo-janssen", silo), ("cd-arrays", cd_arrays), ("force-pdf", force_pdf),
                    ("force-pdf wet", force_pdf_wet), ("pour", pour)):
        try:
            f(root)
        except (OSError, KeyError, ValueError, IndexError) as e:
            print(f"FAIL {name}: its outputs could not be read: {e!r}")
            failures.append(name)
    print(f"{len(failures)} failure(s)" + (": " + "; ".join(failures) if failures else ""))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
