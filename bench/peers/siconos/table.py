#!/usr/bin/python3
"""Turns raw.tsv (one line per run, written by run.sh) into results.md.

Per (problem, tolerance, solver): the median solve time over the repeats, the iterations of
the median run, the largest independent error over the repeats. A run's time is its warm time
(the median of its solves after the first, in one process) when it solved more than once, else
its one solve's; its cold time is its first solve's (a fresh process: page faults included). "Converged" means every repeat
ran to the end and its independent error is <= the tolerance: the same judge for both codes,
whatever each solver says about itself. "Siconos best" is the converged Siconos candidate with
the smallest median time (NSGS included)."""
import argparse
import csv
import re
import statistics
from collections import OrderedDict, defaultdict


def fnum(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return None


def ms(t):
    return "—" if t is None else f"{t * 1e3:.3g}"


def err(e):
    return "—" if e is None else f"{e:.1e}"


def sable_iters(text):
    """'501 NLGS sweeps (stagnating), then 13 Newton steps' -> '501+13N'."""
    m = re.match(r"\s*(\d+)(?:.*?then (\d+) Newton)?", text or "")
    if not m:
        return text or "—"
    return m.group(1) + (f"+{m.group(2)}N" if m.group(2) else "")


def run_time(r):
    """A run's warm time when it solved more than once, else its one solve's time."""
    warm = fnum(r.get("warm_seconds"))
    solves = fnum(r.get("solves")) or 1
    return warm if solves > 1 and warm is not None else fnum(r["seconds"])


class Group:
    """The repeats of one solver on one problem at one tolerance."""

    def __init__(self, rows, tol):
        self.rows = rows
        ok = [r for r in rows if r["status"] == "ok"]
        self.failure = next((r["status"] for r in rows if r["status"] != "ok"), None)
        ok = [r for r in ok if fnum(r["seconds"]) is not None]
        times = [run_time(r) for r in ok]
        self.time = statistics.median(times) if times else None
        colds = [fnum(r["seconds"]) for r in ok]
        self.cold = statistics.median(colds) if colds else None
        # iterations of the run whose time is closest to the median (they rarely differ)
        mid = min(ok, key=lambda r: abs(run_time(r) - self.time)) if times else None
        self.iters = mid["iterations"] if mid else ""
        indeps = [fnum(r["indep_error"]) for r in ok]
        self.indep = max(indeps) if indeps and None not in indeps else None
        selfs = [fnum(r["self_error"]) for r in ok if fnum(r["self_error"]) is not None]
        self.self_err = max(selfs) if selfs else None
        self.infos = sorted({r["info"] for r in ok})
        self.converged = (self.failure is None and self.indep is not None and self.indep <= tol)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("raw")
    ap.add_argument("out")
    for k in ("machine", "date", "load", "siconos", "sable", "command", "repeats", "timeout",
              "inproc"):
        ap.add_argument("--" + k, required=True)
    a = ap.parse_args()

    with open(a.raw, newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    problems = OrderedDict()  # name -> (dim, contacts), in run order
    by = defaultdict(list)  # (problem, tol, code, solver) -> rows
    for r in rows:
        problems.setdefault(r["problem"], (r["dim"], r["contacts"]))
        by[(r["problem"], r["tol"], r["code"], r["solver"])].append(r)
    tols = sorted({r["tol"] for r in rows}, key=float, reverse=True)
    unreadable = {k[0] for k, v in by.items() if v[0]["status"] == "unreadable"}
    sicver = a.siconos.split()[1] if len(a.siconos.split()) > 1 else a.siconos

    L = []
    L.append("# Sable vs Siconos numerics: frictional-contact solvers\n")
    L.append(f"- Machine: {a.machine} (a shared VM: times are medians of {a.repeats} runs)")
    L.append(f"- Date: {a.date}")
    L.append(f"- Load average (1/5/15 min) at start; at end: {a.load}. Other work on the "
             "machine competes for its 2 cores: what runs beside the benchmark shows in the "
             "times, most on the largest problems (compare medians, not single runs).")
    L.append(f"- Siconos: {a.siconos}; Sable: {a.sable}")
    L.append(f"- Command: `{a.command}` (one problem per process, {a.timeout} s limit each)")
    L.append(f"- Each process solves its problem up to {a.inproc} times from r = 0 (Siconos: "
             "a freshly read copy and fresh options each time), further solves only while "
             "its solves took under 0.1 s in all. A run's time is its warm time, the median of "
             "its solves after the first (a solver called step after step), or its one solve's "
             "when it solved once (the long problems, where start-up costs are negligible); "
             "the cold time (the first solve in a fresh process, page faults of the first touch "
             "of code and data included) is summed in the totals. Iterations and errors are "
             "the first solve's (Sable checks that its later solves give the same bits).")
    L.append("- Times are solve only (file reading excluded), in ms. e = independent error "
             "(siconos_fc.c, the same routine for both codes; largest over the repeats). "
             "ok = every repeat finished with e <= tolerance. Iterations as each solver "
             "counts them (Sable: NLGS sweeps, +kN = k semismooth Newton steps after them).")
    L.append("- Sable runs with its defaults but the tolerance (at most 1000 NLGS sweeps, then "
             "at most 100 semismooth Newton steps, per apps/sable/main.cpp).")
    L.append("- Siconos best = the fastest converged of NSGS, NSN_AC, NSN_AC_TEST, NSN_FB, "
             "NSN_NM, PROX, ADMM (3D) or NSGS, CPG, LEMKE, ENUM (2D), Siconos' default options "
             "but the tolerance and the iteration cap (100000 first-order, 1000 Newton/PROX).")
    L.append("- 2D problems stored as CSC (storage 2) are converted to sparse-block before "
             "Siconos' solve (not timed): fc2d_driver aborts on that storage.\n")

    totals = {}
    for tol_s in tols:
        tol = float(tol_s)
        L.append(f"## Tolerance {tol_s}\n")
        L.append("| problem | d | contacts | Sable it | Sable ms | Sable e | ok "
                 "| NSGS it | NSGS ms | NSGS e | ok | best | best it | best ms | best e |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        per_solver = defaultdict(lambda: [0, 0.0])  # solver -> [count, sum of times]
        head = defaultdict(list)  # which solver converged where, with its time
        cold = defaultdict(float)  # sable / NSGS / best -> sum of cold times where converged
        for name, (dim, nc) in problems.items():
            sg = Group(by[(name, tol_s, "sable", "sable")], tol)
            s_cells = [sable_iters(sg.iters), ms(sg.time)]
            if name in unreadable:
                cells = s_cells + [f"n/a (self {err(fnum(sg.self_err))})", "—",
                                   f"not readable by Siconos {sicver}"] + ["—"] * 7
                L.append(f"| {name} | {dim} | {nc} | " + " | ".join(cells) + " |")
                continue
            s_cells += [err(sg.indep), "yes" if sg.converged else "no"]
            if sg.failure:
                s_cells[0] = sg.failure
            if sg.converged:
                head["sable"].append((name, sg.time))
                cold["sable"] += sg.cold
            groups = {k[3]: Group(v, tol) for k, v in by.items()
                      if k[0] == name and k[1] == tol_s and k[2] == "siconos"}
            for s, g in groups.items():
                if g.converged:
                    per_solver[s][0] += 1
                    per_solver[s][1] += g.time
            ng = groups.get("NSGS")
            n_cells = ([ng.failure or ng.iters, ms(ng.time), err(ng.indep),
                        "yes" if ng.converged else "no"] if ng else ["—"] * 4)
            if ng and ng.converged:
                head["NSGS"].append((name, ng.time))
                cold["NSGS"] += ng.cold
            conv = [(g.time, s) for s, g in groups.items() if g.converged]
            if conv:
                t, s = min(conv)
                bg = groups[s]
                b_cells = [s, bg.iters, ms(bg.time), err(bg.indep)]
                head["best"].append((name, t))
                cold["best"] += bg.cold
            else:
                done = [(g.indep, s) for s, g in groups.items() if g.indep is not None]
                lo = min(done) if done else (None, "—")
                b_cells = ["none", "—", "—", f"lowest {err(lo[0])} ({lo[1]})"]
            L.append(f"| {name} | {dim} | {nc} | " + " | ".join(s_cells + n_cells + b_cells)
                     + " |")
        totals[tol_s] = (head, per_solver)
        n_judged = len(problems) - len(unreadable)
        L.append("")
        L.append(f"Totals at {tol_s} over the {n_judged} problems Siconos can read "
                 f"(sum of median times over the problems each converged on):\n")
        L.append("| solver | converged | sum of medians (ms) | cold: sum of first solves (ms) |")
        L.append("|---|---|---|---|")
        for label, key in (("Sable", "sable"), ("Siconos NSGS", "NSGS"), ("Siconos best", "best")):
            h = head[key]
            L.append(f"| {label} | {len(h)}/{n_judged} | {ms(sum(t for _, t in h))} "
                     f"| {ms(cold[key])} |")
        for s, (c, t) in sorted(per_solver.items(), key=lambda x: (-x[1][0], x[1][1])):
            L.append(f"| Siconos {s} (candidate) | {c}/{n_judged} | {ms(t)} | |")
        # head to head on the problems both converged on: sums over the same set
        for other in ("NSGS", "best"):
            s_t = dict(head["sable"])
            o_t = dict(head[other])
            both = [p for p in s_t if p in o_t]
            faster = [p for p in both if o_t[p] < s_t[p]]
            L.append(f"\nBoth Sable and Siconos {other} converged on {len(both)} problems: "
                     f"Sable {ms(sum(s_t[p] for p in both))} ms, Siconos {other} "
                     f"{ms(sum(o_t[p] for p in both))} ms in all. Siconos {other} faster on "
                     f"{len(faster)}: " + (", ".join(f"{p} ({ms(o_t[p])} vs {ms(s_t[p])} ms)"
                                                    for p in faster) or "none") + ".")
        L.append("")

    # Notes: guards, and where a solver's word and the judge's disagree.
    L.append("## Notes (generated from raw.tsv)\n")
    guard = sorted({(k[0], k[3], k[1], r["status"]) for k, v in by.items()
                    for r in v if r["status"] not in ("ok", "unreadable")})
    L.append("Solves stopped by the guard (timeout) or that crashed; such a pair is not run "
             "again in later repeats (a 1e-4 timeout also skips 1e-6):\n")
    L.extend(f"- {p}: {s} at {t}: {st}" for p, s, t, st in guard)
    if not guard:
        L.append("- none")
    if unreadable:
        L.append(f"\nNot readable by Siconos {sicver} (built without FCLIB; its reader aborts), "
                 "so no independent error and no Siconos run: " + ", ".join(sorted(unreadable))
                 + ". Sable's own residual is shown instead.")
    # A solver's own verdict against the judge's: listed one by one. Errors that merely differ
    # in size (a different formula or scaling, same verdict) are summarised per solver.
    L.append("\nWhere a solver's own verdict (Siconos: info == 0; Sable: its residual <= "
             "tolerance) differs from the judge's (independent error <= tolerance):\n")
    n = 0
    ratios = defaultdict(list)  # solver -> [(self / indep, problem, tol)]
    for (p, tol_s, code, s), v in by.items():
        if p in unreadable:
            continue
        g = Group(v, float(tol_s))
        if g.self_err is None or g.indep is None:
            continue
        says_ok = (g.infos == ["0"]) if code == "siconos" else g.self_err <= float(tol_s)
        if says_ok != g.converged:
            n += 1
            word = f"info {','.join(g.infos)}" if code == "siconos" else "Sable"
            L.append(f"- {p}, {s} at {tol_s}: self {err(g.self_err)} ({word}), "
                     f"independent {err(g.indep)}")
        elif (max(g.self_err, g.indep) > 1e-12  # below that both are roundoff
              and max(g.self_err, g.indep) > 10 * max(min(g.self_err, g.indep), 1e-300)):
            ratios[s].append((g.self_err / max(g.indep, 1e-300), p, tol_s))
    if n == 0:
        L.append("- none")
    L.append("\nSame verdict, but the self-reported and the independent error differ by more "
             "than 10x, the larger above 1e-12 (self / independent):\n")
    for s, lst in sorted(ratios.items()):
        lo, hi = min(lst), max(lst)
        L.append(f"- {s}: {len(lst)} (problem, tolerance) pairs, ratio {lo[0]:.2g} "
                 f"({lo[1]} at {lo[2]}) to {hi[0]:.2g} ({hi[1]} at {hi[2]})")
    if not ratios:
        L.append("- none")
    neither = []
    for tol_s in tols:
        head, _ = totals[tol_s]
        got = {p for lst in head.values() for p, _ in lst}
        neither += [f"{p} at {tol_s}" for p in problems if p not in got and p not in unreadable]
    L.append("\nProblems no solver (Sable or any Siconos candidate) converged on: "
             + (", ".join(neither) or "none") + ".")

    with open(a.out, "w") as f:
        f.write("\n".join(L) + "\n")


if __name__ == "__main__":
    main()
