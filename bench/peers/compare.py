#!/usr/bin/env python3
"""Parse the runs of bench/peers/compare.sh and print the LIGGGHTS 3.8 vs Sable table (markdown).

Usage: compare.py RUNROOT [--out FILE]

RUNROOT holds meta.txt (key=value lines written by compare.sh) and runs/rR_cC_CODE/ with
  CODE = liggghts: log.liggghts (LIGGGHTS' log), mem.rank*.txt (GNU time -v, one per rank),
                   out/bed.dump (final dense bed: id type x y z radius vx vy vz c_cn)
  CODE = sable:    stderr.txt (stage lines), mem.rank0.txt (GNU time -v), sim/series.csv,
                   sim/vtk/grains_<step>.vtp (the last one is the end of the dense stage)

Speed: particle-steps/s = grains * steps / seconds of the phase's loop.
  LIGGGHTS: the "Loop time of T on P procs for N steps with A atoms" line of the run between
            PHASE_A_BEGIN/END (settling) and PHASE_B_BEGIN/END (dense).
  Sable:    the stage lines "stage 'settle' done: ..." and "stage 'dense' done: ..."; the rate is
            taken from the printed grain-steps/s (4 significant digits; the printed seconds have
            only 2 decimals).
Memory: peak resident set size from GNU time; for LIGGGHTS on 2 ranks each rank is wrapped by
  its own `time` and the ranks' peaks are summed (shared pages, e.g. the MPI and C libraries, are
  then counted once per rank). Sable is one process whatever its thread count.
Physics of the bed at the end of phase (b) -- see bulk_region() for the region:
  solid fraction   sum of the volumes 4/3 pi r^3 of the grains whose CENTRES lie in the bulk
                   region, divided by the region's volume (whole grains are counted, not clipped
                   at the region's faces: unbiased on average, +-~0.5 % noise at this size)
  coordination     mean contacts per grain over the same grains. LIGGGHTS: c_cn of compute
                   contact/atom (grain-grain only); Sable: PointData "coordination" (grain-grain
                   plus grain-wall, but no grain of the bulk region can touch a wall)
  floor / weight   vertical force between the bottom wall and the grains at the last step of
                   phase (b), over the bed's weight N rho 4/3 pi r^3 g. LIGGGHTS: the last thermo
                   value of c_fzb (force on the grains, +z); Sable: -wall_box.zlo_fz_N of the
                   last series.csv row (Sable reports the force on the wall).
"""
import math
import os
import re
import statistics
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "scripts"))
import vtkxml  # noqa: E402

RHO = 2500.0
G = 9.81
BOX = (0.030, 0.030)  # x and y extent of the box (m); walls at 0 and BOX

TARGETS = {
    "dense": 2.0,          # Sable / LIGGGHTS particle-steps/s, dense phase, 1 and 2 cores
    "settle": 1.5,         # same, settling phase
    "scaling": 1.8,        # Sable 2 threads / Sable 1 thread, dense phase
    "memory": 1.0,         # Sable peak / LIGGGHTS peak <= 1
    "solid_fraction": 0.01,  # relative difference
    "coordination": 0.02,
    "floor_force": 0.03,
}


# ----------------------------------------------------------------------------- parsing helpers

def read_meta(root):
    meta = {}
    path = os.path.join(root, "meta.txt")
    if os.path.exists(path):
        for line in open(path):
            if "=" in line:
                k, v = line.rstrip("\n").split("=", 1)
                meta[k.strip()] = v.strip()
    return meta


def peak_rss_mib(run_dir):
    """Sum over mem.rank*.txt of GNU time's 'Maximum resident set size (kbytes)'."""
    total, n = 0, 0
    for name in sorted(os.listdir(run_dir)):
        if not re.fullmatch(r"mem\.rank\d+\.txt", name):
            continue
        m = re.search(r"Maximum resident set size \(kbytes\): (\d+)",
                      open(os.path.join(run_dir, name)).read())
        if not m:
            raise ValueError(f"{run_dir}/{name}: no 'Maximum resident set size' line")
        total += int(m.group(1))
        n += 1
    if n == 0:
        raise ValueError(f"{run_dir}: no mem.rank*.txt")
    return total / 1024.0, n


LOOP_RE = re.compile(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")


def parse_liggghts_log(path):
    """Phase loop times and the last thermo row of phase (b) of one LIGGGHTS log."""
    lines = open(path, errors="replace").read().splitlines()
    marks = {}
    for i, line in enumerate(lines):
        if line.strip() in ("PHASE_A_BEGIN", "PHASE_A_END", "PHASE_B_BEGIN", "PHASE_B_END"):
            marks.setdefault(line.strip(), i)  # the echoed `print "..."` line is not equal to it
    for k in ("PHASE_A_BEGIN", "PHASE_A_END", "PHASE_B_BEGIN", "PHASE_B_END"):
        if k not in marks:
            raise ValueError(f"{path}: no {k} line (run did not finish?)")
    res = {"version": lines[0].strip() if lines else "?"}
    for phase, (b, e) in (("settle", ("PHASE_A_BEGIN", "PHASE_A_END")),
                          ("dense", ("PHASE_B_BEGIN", "PHASE_B_END"))):
        block = lines[marks[b]:marks[e]]
        loops = [LOOP_RE.match(l) for l in block]
        loops = [m for m in loops if m]
        if len(loops) != 1:
            raise ValueError(f"{path}: {len(loops)} 'Loop time' lines in phase {phase}")
        t, procs, steps, atoms = loops[0].groups()
        res[phase] = {"seconds": float(t), "procs": int(procs), "steps": int(steps),
                      "grains": int(atoms)}
        res[phase]["rate"] = res[phase]["grains"] * res[phase]["steps"] / res[phase]["seconds"]
        # thermo: a header line starting with "Step", then rows of numbers
        header, last = None, None
        for l in block:
            tok = l.split()
            if tok and tok[0] == "Step":
                header = tok
            elif header and len(tok) == len(header):
                try:
                    last = [float(x) for x in tok]
                except ValueError:
                    pass
        if header is None or last is None:
            raise ValueError(f"{path}: no thermo rows in phase {phase}")
        res[phase]["thermo"] = dict(zip(header, last))
    return res


def parse_liggghts_dump(path):
    """Last snapshot of a LAMMPS custom dump -> (positions, radii, coordination, box)."""
    lines = open(path).read().splitlines()
    starts = [i for i, l in enumerate(lines) if l.startswith("ITEM: TIMESTEP")]
    if not starts:
        raise ValueError(f"{path}: not a dump file")
    i = starts[-1]
    step = int(lines[i + 1])
    n = int(lines[i + 3])
    box = [tuple(float(v) for v in lines[i + 5 + k].split()[:2]) for k in range(3)]
    cols = lines[i + 8].split()[2:]
    ix, iy, iz, ir, ic = (cols.index(c) for c in ("x", "y", "z", "radius", "c_cn"))
    pos, rad, cn = [], [], []
    for l in lines[i + 9:i + 9 + n]:
        t = l.split()
        pos.append((float(t[ix]), float(t[iy]), float(t[iz])))
        rad.append(float(t[ir]))
        cn.append(float(t[ic]))
    if len(pos) != n:
        raise ValueError(f"{path}: {len(pos)} atom rows, expected {n}")
    return {"step": step, "pos": pos, "radius": rad, "coord": cn, "box": box}


STAGE_RE = re.compile(r"^stage '([^']*)' done: (\d+) steps in (\S+) s, (\S+) grain-steps/s")
DONE_RE = re.compile(r"^done: (\d+) grains, (\d+) steps, .*peak memory (\S+) MiB, "
                     r"state hash ([0-9a-f]+)")


def parse_sable_stderr(path):
    res = {}
    grains = None
    stages = []
    for line in open(path, errors="replace"):
        line = line.rstrip("\n").split("\r")[-1]  # progress lines may use carriage returns
        m = STAGE_RE.match(line)
        if m:
            stages.append(m.groups())
        m = DONE_RE.match(line)
        if m:
            grains = int(m.group(1))
            res["total_steps"] = int(m.group(2))
            res["self_peak_mib"] = float(m.group(3))
            res["hash"] = m.group(4)
    if grains is None:
        raise ValueError(f"{path}: no final 'done:' line (run did not finish?)")
    if len(stages) != 2:
        raise ValueError(f"{path}: {len(stages)} 'stage ... done' lines, expected 2")
    for phase, (name, steps, secs, rate) in zip(("settle", "dense"), stages):
        steps, rate = int(steps), float(rate)
        res[phase] = {"name": name, "steps": steps, "grains": grains, "rate": rate,
                      "seconds": grains * steps / rate if rate > 0 else float(secs),
                      "printed_seconds": float(secs)}
    res["grains"] = grains
    return res


def parse_series_last(path):
    rows = [l.strip() for l in open(path) if l.strip()]
    header = rows[0].split(",")
    last = [float(x) for x in rows[-1].split(",")]
    return dict(zip(header, last))


def parse_vtp_grains(path):
    f = vtkxml.read(path)
    for name in ("radius", "coordination"):
        if name not in f.point_data:
            raise ValueError(f"{path}: no DataArray {name} in PointData")
    return {"pos": [tuple(p) for p in f.points.tolist()],
            "radius": f.point_data["radius"].tolist(),
            "coord": [float(z) for z in f.point_data["coordination"]]}


def last_vtp(vtk_dir):
    best = None
    for name in os.listdir(vtk_dir):
        m = re.fullmatch(r"grains_(\d+)\.vtp", name)
        if m and (best is None or int(m.group(1)) > best[0]):
            best = (int(m.group(1)), name)
    if best is None:
        raise ValueError(f"{vtk_dir}: no grains_*.vtp")
    return best[0], os.path.join(vtk_dir, best[1])


# ----------------------------------------------------------------------------- physics

NCOL = 10  # the free surface is measured on NCOL x NCOL columns (3 mm = 2 d wide)


def bulk_region(pos, radius):
    """The bulk region: an axis-aligned box
         3 d <= x <= Lx - 3 d,   3 d <= y <= Ly - 3 d,   3 d <= z <= z_surface - 3 d
    with d the mean grain diameter, Lx = Ly = 30 mm the box (walls at 0 and L), and z_surface the
    free surface: the x-y plane is cut into 10 x 10 columns (2 d wide), in each column the
    highest grain top (centre z + r) is taken, and z_surface is the mean of these 100 heights.
    3 d from the floor, the side walls and the free surface excludes the wall and surface layers
    whose packing is looser."""
    d = 2.0 * statistics.fmean(radius)
    lx, ly = BOX
    top = [[None] * NCOL for _ in range(NCOL)]
    for (x, y, z), r in zip(pos, radius):
        i = min(NCOL - 1, max(0, int(x / lx * NCOL)))
        j = min(NCOL - 1, max(0, int(y / ly * NCOL)))
        h = z + r
        if top[i][j] is None or h > top[i][j]:
            top[i][j] = h
    heights = [h for row in top for h in row if h is not None]
    z_surface = statistics.fmean(heights)
    return {"lo": (3 * d, 3 * d, 3 * d), "hi": (lx - 3 * d, ly - 3 * d, z_surface - 3 * d),
            "z_surface": z_surface, "d": d}


def bed_physics(pos, radius, coord, fz_floor):
    reg = bulk_region(pos, radius)
    lo, hi = reg["lo"], reg["hi"]
    vol_region = (hi[0] - lo[0]) * (hi[1] - lo[1]) * max(0.0, hi[2] - lo[2])
    solid, zsum, n_in = 0.0, 0.0, 0
    for p, r, c in zip(pos, radius, coord):
        if all(lo[k] <= p[k] <= hi[k] for k in range(3)):
            solid += 4.0 / 3.0 * math.pi * r ** 3
            zsum += c
            n_in += 1
    weight = sum(RHO * 4.0 / 3.0 * math.pi * r ** 3 for r in radius) * G
    return {
        "solid_fraction": solid / vol_region if vol_region > 0 else float("nan"),
        "coordination": zsum / n_in if n_in else float("nan"),
        "floor_force": fz_floor / weight,
        "bulk_grains": n_in,
        "z_surface": reg["z_surface"],
    }


# ----------------------------------------------------------------------------- gathering

RUN_RE = re.compile(r"r(\d+)_c(\d+)_(liggghts|sable)")


def gather(root):
    runs = []
    rdir = os.path.join(root, "runs")
    for name in sorted(os.listdir(rdir)):
        m = RUN_RE.fullmatch(name)
        if not m:
            continue
        rep, cores, code = int(m.group(1)), int(m.group(2)), m.group(3)
        d = os.path.join(rdir, name)
        run = {"rep": rep, "cores": cores, "code": code, "dir": d}
        try:
            run["mem_mib"], run["processes"] = peak_rss_mib(d)
            if code == "liggghts":
                log = parse_liggghts_log(os.path.join(d, "log.liggghts"))
                run.update(settle=log["settle"], dense=log["dense"], version=log["version"])
                dump = parse_liggghts_dump(os.path.join(d, "out", "bed.dump"))
                fz = log["dense"]["thermo"]["fzb"]  # force of the floor on the grains (+z)
                run["final_step"] = dump["step"]
                run["phys"] = bed_physics(dump["pos"], dump["radius"], dump["coord"], fz)
            else:
                se = parse_sable_stderr(os.path.join(d, "stderr.txt"))
                run.update(settle=se["settle"], dense=se["dense"], hash=se["hash"])
                row = parse_series_last(os.path.join(d, "sim", "series.csv"))
                step, vtp = last_vtp(os.path.join(d, "sim", "vtk"))
                if int(row["step"]) != step:
                    raise ValueError(f"{d}: last series.csv row is step {int(row['step'])}, "
                                     f"last grains VTK is step {step}: set csv_interval to a "
                                     "divisor of the step counts")
                g = parse_vtp_grains(vtp)
                fz = -row["wall_box.zlo_fz_N"]  # Sable: force on the wall; on the grains = -it
                run["final_step"] = step
                run["phys"] = bed_physics(g["pos"], g["radius"], g["coord"], fz)
        except (OSError, ValueError, KeyError, IndexError) as e:
            run["error"] = str(e)
        runs.append(run)
    return runs


# ----------------------------------------------------------------------------- table

def med(v):
    return statistics.median(v) if v else float("nan")


def fmt_m(x):
    return "n/a" if x != x else f"{x / 1e6:.2f}"


def yes(ok):
    return "n/a" if ok is None else ("yes" if ok else "**NO**")


def build_table(root, meta, runs):
    ok_runs = [r for r in runs if "error" not in r]
    cores_list = sorted({r["cores"] for r in runs})
    stiff = meta.get("variant") == "stiff"

    def sel(code, cores):
        return [r for r in ok_runs if r["code"] == code and r["cores"] == cores]

    out = []
    w = out.append
    checks = []  # (target's text, True / False / None when not measurable)
    header_section(w, meta, ok_runs, stiff)
    speed_section(w, sel, cores_list, checks)
    memory_section(w, sel, cores_list, checks)
    physics_section(w, sel, cores_list, checks, stiff)
    met = [n for n, ok in checks if ok]
    missed = [n for n, ok in checks if ok is False]
    unknown = [n for n, ok in checks if ok is None]
    w(f"**Targets met: {len(met)} of {len(checks)}.**" +
      (" Not met: " + "; ".join(missed) + "." if missed else "") +
      (" Not measurable (no data, or zero/NaN reference): " + "; ".join(unknown) + "."
       if unknown else ""))
    w("")
    w("## Runs")
    w("")
    w("| run | code | cores | (a) s | (a) M p-steps/s | (b) s | (b) M p-steps/s | peak MiB | "
      "solid fr. | coord. | floor/weight | bulk grains | note |")
    w("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in sorted(runs, key=lambda r: (r["rep"], r["cores"], r["code"])):
        if "error" in r:
            w(f"| {r['rep']} | {r['code']} | {r['cores']} | | | | | | | | | | "
              f"FAILED: {r['error']} |")
            continue
        p = r["phys"]
        note = f"state hash {r['hash']}" if r["code"] == "sable" else f"{r['processes']} rank(s)"
        w(f"| {r['rep']} | {r['code']} | {r['cores']} | {r['settle']['seconds']:.2f} | "
          f"{fmt_m(r['settle']['rate'])} | {r['dense']['seconds']:.2f} | "
          f"{fmt_m(r['dense']['rate'])} | {r['mem_mib']:.1f} | {p['solid_fraction']:.4f} | "
          f"{p['coordination']:.3f} | {p['floor_force']:.4f} | {p['bulk_grains']} | {note} |")
    return "\n".join(out) + "\n"


def header_section(w, meta, ok_runs, stiff):
    w(f"# LIGGGHTS 3.8 vs Sable on the pour bed ({meta.get('variant', '?')} variant)")
    w("")
    w(f"- {meta.get('date', '?')}, {meta.get('machine', '?')}")
    w(f"- 20,000 grains, E = {meta.get('E', '?')} Pa, dt = {meta.get('dt', '?')} s; "
      f"phase (a) settling {meta.get('nsettle', '?')} steps, phase (b) dense "
      f"{meta.get('nstatic', '?')} steps; {meta.get('repeats', '?')} repeat(s), codes "
      "alternating, each run alone on the machine")
    versions = sorted({r["version"] for r in ok_runs if r["code"] == "liggghts"})
    w(f"- LIGGGHTS: {'; '.join(versions) or '?'}, {meta.get('liggghts', '?')}; 2 cores = `mpirun -np 2 --bind-to core`, "
      "`processors 2 1 1`")
    w(f"- Sable: {meta.get('sable', '?')}; 2 cores = `--threads 2`")
    w(f"- command: `{meta.get('command', '?')}`")
    if stiff:
        w("- stiff variant: phase (a) is the start of the fall (not a settled bed) and phase (b) "
          "continues it; the physics rows compare the two beds at the same instant, for "
          "information only (no target)")
    w("")


def speed_section(w, sel, cores_list, checks):
    def per_repeat_scaling(code):
        one = {r["rep"]: r["dense"]["rate"] for r in sel(code, 1)}
        two = {r["rep"]: r["dense"]["rate"] for r in sel(code, 2)}
        return ", ".join(f"{two[k] / one[k]:.2f}x" for k in sorted(one) if k in two) or "n/a"

    w("## Speed (million particle-steps/s: median, min-max over repeats)")
    w("")
    w("| phase | cores | LIGGGHTS | Sable | Sable / LIGGGHTS (medians) | target | vs target | met |")
    w("|---|---|---|---|---|---|---|---|")
    for phase, label in (("settle", "(a) settling"), ("dense", "(b) dense")):
        for c in cores_list:
            lv = [r[phase]["rate"] for r in sel("liggghts", c)]
            sv = [r[phase]["rate"] for r in sel("sable", c)]
            ratio = med(sv) / med(lv) if lv and sv else float("nan")
            t = TARGETS[phase]
            ok = None if ratio != ratio else ratio >= t
            checks.append((f"{label}, {c} core(s): speed ratio >= {t}", ok))
            rng = lambda v: f"{fmt_m(med(v))} ({fmt_m(min(v))}-{fmt_m(max(v))})" if v else "n/a"
            w(f"| {label} | {c} | {rng(lv)} | {rng(sv)} | {ratio:.2f}x | >= {t:.1f}x | "
              f"{ratio - t:+.2f}x | {yes(ok)} |")
    if 1 in cores_list and 2 in cores_list:
        ls = med([r["dense"]["rate"] for r in sel("liggghts", 2)]) / \
            med([r["dense"]["rate"] for r in sel("liggghts", 1)]) if sel("liggghts", 1) and sel("liggghts", 2) else float("nan")
        ss = med([r["dense"]["rate"] for r in sel("sable", 2)]) / \
            med([r["dense"]["rate"] for r in sel("sable", 1)]) if sel("sable", 1) and sel("sable", 2) else float("nan")
        t = TARGETS["scaling"]
        ok = None if ss != ss else ss >= t
        checks.append((f"(b) dense: Sable 2 threads / 1 thread >= {t}", ok))
        w(f"| (b) dense: 2 cores / 1 core | - | {ls:.2f}x | {ss:.2f}x | - | Sable >= {t:.1f}x | "
          f"{ss - t:+.2f}x | {yes(ok)} |")
        w("")
        w("Dense phase, 2 cores / 1 core per repeat, for information (the target reads the "
          f"medians): Sable {per_repeat_scaling('sable')}; LIGGGHTS "
          f"{per_repeat_scaling('liggghts')}. compare.sh runs Sable's two back to back, with "
          "LIGGGHTS' on either side.")
    w("")


def memory_section(w, sel, cores_list, checks):
    w("## Peak memory (MiB, median over repeats; LIGGGHTS: sum over ranks)")
    w("")
    w("| cores | LIGGGHTS | Sable | Sable / LIGGGHTS | target | met |")
    w("|---|---|---|---|---|---|")
    for c in cores_list:
        lm = med([r["mem_mib"] for r in sel("liggghts", c)])
        sm = med([r["mem_mib"] for r in sel("sable", c)])
        ratio = sm / lm if lm == lm and sm == sm else float("nan")
        ok = None if ratio != ratio else ratio <= TARGETS["memory"]
        checks.append((f"memory, {c} core(s): Sable <= LIGGGHTS", ok))
        w(f"| {c} | {lm:.1f} | {sm:.1f} | {ratio:.2f} | <= 1.00 | {yes(ok)} |")
    w("")


def physics_section(w, sel, cores_list, checks, stiff):
    w("## The bed at the end of phase (b) (median over repeats)")
    w("")
    w("Bulk region: 3 d <= x, y <= 30 mm - 3 d and 3 d <= z <= z_surface - 3 d, z_surface = mean "
      "over 10 x 10 columns (2 d wide) of the highest grain top; solid fraction = volume of the "
      "grains whose centres are in the region / region volume; coordination = mean contacts per "
      "grain of those grains; floor / weight = vertical force of the bottom wall on the grains "
      "at the last step / (N rho 4/3 pi r^3 g). One bed per code is one draw: the floor's "
      "share of the weight changes with any round-off (LIGGGHTS' 1- and 2-rank beds differ); "
      "`bench/peers/seeds.sh` compares the two codes' distributions over seeds, "
      "`bench/peers/roundoff.sh` over trajectories of one bed.")
    w("")
    w("| quantity | cores | LIGGGHTS | Sable | Sable - LIGGGHTS (relative) | target | met |")
    w("|---|---|---|---|---|---|---|")
    for q, label, f in (("solid_fraction", "bulk solid fraction", "{:.4f}"),
                        ("coordination", "bulk coordination", "{:.3f}"),
                        ("floor_force", "floor force / weight", "{:.4f}")):
        for c in cores_list:
            lv = med([r["phys"][q] for r in sel("liggghts", c)])
            sv = med([r["phys"][q] for r in sel("sable", c)])
            rel = (sv - lv) / abs(lv) if lv == lv and sv == sv and lv != 0 else float("nan")
            t = TARGETS[q]
            ok = None if (rel != rel or stiff) else abs(rel) <= t
            if not stiff:
                checks.append((f"{label}, {c} core(s): within {t * 100:.0f} %", ok))
            w(f"| {label} | {c} | {f.format(lv)} | {f.format(sv)} | {rel * 100:+.2f} % | "
              f"{'info' if stiff else f'+-{t * 100:.0f} %'} | {yes(ok)} |")
    w("")


def main(argv):
    args = [a for a in argv[1:]]
    out_file = None
    if "--out" in args:
        i = args.index("--out")
        out_file = args[i + 1]
        del args[i:i + 2]
    if len(args) != 1:
        print(__doc__.split("\n\n")[0], file=sys.stderr)
        print("usage: compare.py RUNROOT [--out FILE]", file=sys.stderr)
        return 2
    root = args[0]
    meta = read_meta(root)
    runs = gather(root)
    if not runs:
        print(f"no runs under {root}/runs", file=sys.stderr)
        return 1
    text = build_table(root, meta, runs)
    sys.stdout.write(text)
    if out_file:
        os.makedirs(os.path.dirname(os.path.abspath(out_file)), exist_ok=True)
        with open(out_file, "w") as f:
            f.write(text)
    return 1 if any("error" in r for r in runs) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
