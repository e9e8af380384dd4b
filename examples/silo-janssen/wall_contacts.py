#!/usr/bin/python3
"""Side-wall contacts of the 2D silo while its bottom wall descends, one contact at a time.

Usage: wall_contacts.py RUN_DIR...   (each RUN_DIR holds its scenario .toml and snapshots/)

Pools the descent snapshots of all runs: those strictly between end_of_stage_1 and
end_of_stage_2, plus end_of_stage_2 (the snapshots `sable analyze` pools in descent_scan.sh
and run.sh). Per side-wall contact (fn > 0): on the Coulomb cone if |ft| >= 0.99 mu fn (the
analysis' default eps = 0.01); ft is signed, > 0 upwards on the grain, so sum ft / sum fn is
the walls' shear/normal. The disk rolls down the wall without slip if its contact point is at
rest on the wall: slip = v_y - s w R (s = +1 on a wall facing +x, -1 facing -x) below
0.1 v_wall. Prints the numbers and writes them to wall_contacts.json beside the first run.
"""
import glob, json, os, sys, tomllib
import numpy as np
import h5py

# fn / median fn: the weak network (< 0.1) up to the strong chains (> 4), which are the
# contacts that stay off the cone while their disks roll.
BANDS = [0.0, 0.1, 1.0, 2.0, 4.0, np.inf]


def fail(msg):
    print(f"wall_contacts.py: {msg}", file=sys.stderr)
    sys.exit(2)


def snapshot(path):
    if not os.path.isfile(path):
        fail(f"{path}: no such snapshot")
    try:
        f = h5py.File(path, "r")
    except OSError:
        fail(f"{path}: not an HDF5 file")
    kind = f.attrs.get("format", b"")
    if (kind.decode() if isinstance(kind, bytes) else kind) != "sable-snapshot":
        fail(f"{path}: not a Sable snapshot")
    if f.attrs["dimension"] != 2:
        fail(f"{path}: a {f.attrs['dimension']}D snapshot; this study is of the 2D silo")
    return f


def scenario(run):
    tomls = glob.glob(os.path.join(run, "*.toml"))
    if len(tomls) != 1:
        fail(f"{run}: expected one scenario .toml in the run directory, found {len(tomls)}")
    with open(tomls[0], "rb") as fh:
        sc = tomllib.load(fh)
    # One material, no pair override: every side-wall contact has the material's friction.
    if len(sc.get("material", [])) != 1 or "material_pair" in sc:
        fail(f"{tomls[0]}: expected a single [[material]] and no [[material_pair]]")
    mu = sc["material"][0]["friction"]
    # The descent is stage 2: the speed of the wall it moves (the bottom).
    stages = sc.get("stage", []) + [{}, {}]
    speeds = [np.linalg.norm(u) for u in stages[1].get("wall_velocity", {}).values()]
    if not speeds or max(speeds) == 0.0:
        fail(f"{tomls[0]}: stage 2 moves no wall, so there is no descent")
    # Side walls: planes whose normal is horizontal (gravity along -y), by name.
    side = {w["name"]: w["normal"][0] for w in sc["wall"]
            if w.get("type") == "plane" and w.get("normal", [0, 1])[1] == 0.0}
    return mu, max(speeds), side


def run_contacts(run):
    """Per-contact columns (fn, ft, m = |ft| / (mu fn), slip / v_wall) and per-snapshot rows."""
    if not os.path.isdir(run):
        fail(f"{run}: no such directory")
    if not os.path.isdir(os.path.join(run, "snapshots")):
        fail(f"{run}: not a run directory (no snapshots/)")
    mu, vwall, side = scenario(run)
    sn = os.path.join(run, "snapshots")
    f1, f2 = snapshot(f"{sn}/end_of_stage_1.h5"), snapshot(f"{sn}/end_of_stage_2.h5")
    t1, s1, s2 = f1.attrs["time"], f1.attrs["step"], f2.attrs["step"]
    files = [p for p in sorted(glob.glob(f"{sn}/step_*.h5"))
             if s1 < int(os.path.basename(p)[5:-3]) < s2] + [f"{sn}/end_of_stage_2.h5"]
    recs, rows = [], []
    for path in files:
        f = snapshot(path)
        names = [n.decode() for n in f["walls/names"][:]]
        v, w, R = f["particles/v"][:], f["particles/w"][:, 0], f["particles/radius"][:]
        i, wall, F = (f[f"neighbors/wall_pairs/{k}"][:] for k in ("i", "wall", "force"))
        # Wall normal x component per pair (0 for the bottom); wall_pairs also lists grains
        # near a wall without touching it (zero force): fn > 0 keeps the contacts.
        s = np.array([side.get(names[k], 0.0) for k in wall])
        fn, ft = F[:, 0] * s, F[:, 1]
        keep = (s != 0.0) & (fn > 0.0)
        fn, ft, s, i = fn[keep], ft[keep], s[keep], i[keep]
        slip = (v[i, 1] - s * w[i] * R[i]) / vwall
        recs.append(np.column_stack([fn, ft, np.abs(ft) / (mu * fn), slip]))
        on = np.abs(ft) >= 0.99 * mu * fn
        rows.append(dict(run=os.path.basename(os.path.normpath(run)), snapshot=os.path.basename(path),
                         descent_mm=(f.attrs["time"] - t1) * vwall * 1e3, n=int(len(fn)),
                         on_cone=float(on.mean()) if len(fn) else None,
                         shear_over_normal=float(ft.sum() / fn.sum()) if len(fn) else None))
    return mu, vwall, np.vstack(recs), rows


def main(runs):
    if not runs:
        fail("usage: wall_contacts.py RUN_DIR...")
    allrec, rows, inputs = [], [], []
    for run in runs:
        mu, vwall, rec, r = run_contacts(run)
        allrec.append(rec)
        rows += r
        inputs.append(dict(run=run, mu=mu, v_wall_m_s=float(vwall), snapshots=len(r)))
    fn, ft, m, slip = np.vstack(allrec).T
    if len(fn) == 0:
        fail("no side-wall contact in any descent snapshot")
    on = m >= 0.99
    off = ~on
    rolls = np.abs(slip) < 0.1
    fm = np.median(fn)
    bands = []
    for lo, hi in zip(BANDS[:-1], BANDS[1:]):
        b = (fn / fm >= lo) & (fn / fm < hi)
        bands.append(dict(lo=lo, hi=None if np.isinf(hi) else hi, n=int(b.sum()),
                          on_cone=float(on[b].mean()) if b.any() else None))
    pooled = dict(snapshots=len(rows), contacts=int(len(fn)), on_cone=float(on.mean()),
                  shear_over_normal=float(ft.sum() / fn.sum()),
                  off_cone_rolling_without_slip=float(rolls[off].mean()) if off.any() else None,
                  on_cone_rolling_without_slip=float(rolls[on].mean()) if on.any() else None,
                  off_cone_share_of_normal_force=float(fn[off].sum() / fn.sum()))

    def fmt(x):
        return "-" if x is None else f"{x:.3f}"

    mus = ", ".join(f"{x:g}" for x in sorted({r["mu"] for r in inputs}))
    speeds = ", ".join(f"{x * 1e3:g}" for x in sorted({r["v_wall_m_s"] for r in inputs}))
    print(f"Side-wall contacts over the descent, {len(runs)} run(s), {len(rows)} snapshots "
          f"(mu = {mus}, v_wall = {speeds} mm/s)")
    print(f"  contacts {pooled['contacts']}, on the Coulomb cone {fmt(pooled['on_cone'])}, "
          f"sum ft / sum fn {fmt(pooled['shear_over_normal'])}")
    print(f"  rolling without slip (|slip| < 0.1 v_wall): {fmt(pooled['off_cone_rolling_without_slip'])}"
          f" of off-cone contacts, {fmt(pooled['on_cone_rolling_without_slip'])} of on-cone ones")
    print(f"  off-cone share of the wall normal force: {fmt(pooled['off_cone_share_of_normal_force'])}")
    print("  on-cone fraction by fn / median fn:")
    for b in bands:
        hi = "inf" if b["hi"] is None else f"{b['hi']:g}"
        print(f"    [{b['lo']:g}, {hi}): n = {b['n']:5d}, on cone {fmt(b['on_cone'])}")
    print("  per snapshot:\n    run          snapshot             descent_mm     n  on_cone  shear/normal")
    for r in rows:
        print(f"    {r['run']:12s} {r['snapshot']:20s} {r['descent_mm']:10.2f} {r['n']:5d}"
              f"  {fmt(r['on_cone']):>7s}  {fmt(r['shear_over_normal']):>12s}")
    out = os.path.join(os.path.dirname(os.path.abspath(runs[0].rstrip("/"))), "wall_contacts.json")
    with open(out, "w") as fh:
        json.dump(dict(inputs=inputs, on_cone_threshold="|ft| >= 0.99 mu fn",
                       rolling_threshold="|v_y - s w R| < 0.1 v_wall", pooled=pooled,
                       fn_over_median_bands=bands, median_fn_N=float(fm), snapshots=rows),
                  fh, indent=1)
    print(f"  written: {out}")


if __name__ == "__main__":
    main(sys.argv[1:])
