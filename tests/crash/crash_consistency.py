#!/usr/bin/python3
"""Crash consistency: a run killed with SIGKILL at a random moment leaves snapshots from
which a resume reaches the uninterrupted run's final state, bit for bit.

Usage: crash_consistency.py --sable BIN --work DIR [--trials N] [--seed S] SCENARIO...

For each scenario: one uninterrupted run gives the reference state hash (the `done:` line of
`sable run`), its wall time T and its n step snapshots. Then N trials, each on a fresh output
directory: start the run, and SIGKILL it u T / n seconds (u of the mean time between two
snapshots) after its step snapshot number m appeared, m among the first n - 2 and u in
[0, 1) drawn from a generator seeded by (S, scenario, trial): the moments are reproducible
as places in the run's progress, whatever the machine's load. Then take the newest snapshot
(snapshots/step_*.h5 by the step in its name; the temporaries `*.tmp-<pid>` of a write cut
short are ignored); check that `sable info` loads it, that its step is the one in its name
and that its state hash is that of the reference run's snapshot of the same name (the
snapshot is exactly the uninterrupted run's); resume from it into another fresh directory
and check the final state hash against the reference. A leftover `*.tmp-*` in snapshots/
means the kill landed during a snapshot write: those trials are counted and reported, since
they are the point of the test (snapshots are written to a temporary and renamed,
src/sable/io/atomic_file.cpp).

Exit status 0 when every trial passes, 1 otherwise (each failure is printed).
"""
import argparse
import glob
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

HASH_RE = re.compile(r"^done: .*state hash ([0-9a-f]{16})\s*$", re.M)
INFO_STEP_RE = re.compile(r"^\s*step\s+(\d+)\s*$", re.M)
INFO_HASH_RE = re.compile(r"^\s*state hash\s+([0-9a-f]{16})\s*$", re.M)
STEP_FILE_RE = re.compile(r"^step_(\d+)\.h5$")


def run(cmd, log):
    """Run cmd to completion, its output into log; returns (exit status, output)."""
    with open(log, "w") as f:
        status = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    with open(log) as f:
        return status, f.read()


def final_hash(status, text, what):
    m = HASH_RE.search(text)
    if status != 0 or not m:
        raise RuntimeError(f"{what}: exit status {status}, no final hash; output:\n{text[-2000:]}")
    return m.group(1)


def info(sable, snapshot, log):
    """(step, state hash) of a snapshot, as `sable info` reads them; raises if it fails."""
    status, text = run([sable, "info", snapshot], log)
    step, digest = INFO_STEP_RE.search(text), INFO_HASH_RE.search(text)
    if status != 0 or not step or not digest:
        raise RuntimeError(f"sable info {snapshot}: exit status {status}; output:\n{text[-2000:]}")
    return int(step.group(1)), digest.group(1)


def newest_snapshot(snap_dir):
    """The complete step_*.h5 with the highest step, and the temporaries left beside it."""
    names = os.listdir(snap_dir) if os.path.isdir(snap_dir) else []
    temps = sorted(n for n in names if ".tmp-" in n)
    steps = [(int(m.group(1)), n) for n in names if (m := STEP_FILE_RE.match(n))]
    if not steps:
        return None, None, temps
    step, name = max(steps)
    return step, os.path.join(snap_dir, name), temps


def run_and_kill(args, scenario, base, after, wait):
    """Start the run, SIGKILL it `wait` seconds after its snapshot `after` appeared; returns
    (output directory, whether the run had finished before the kill)."""
    killed_dir = os.path.join(base, "killed")
    target = os.path.join(killed_dir, "snapshots", after)
    with open(os.path.join(base, "killed.log"), "w") as log:
        proc = subprocess.Popen([args.sable, "run", scenario, "--out", killed_dir, "--threads",
                                 "1"], stdout=log, stderr=subprocess.STDOUT)
        # Poll every millisecond: a snapshot interval lasts 5-20 ms here.
        while not os.path.exists(target) and proc.poll() is None:
            time.sleep(0.001)
        try:
            proc.wait(timeout=wait)
            return killed_dir, True  # the run ended before the kill was due
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGKILL)
            proc.wait()
            return killed_dir, False


def trial(args, scenario, name, ref, k):
    """One kill, check and resume; returns a dict describing it (raises on a failure)."""
    # The moment: after a seeded one of the reference run's step snapshots (not its last
    # two), a seeded fraction of the mean time between snapshots later. Counted from the run's
    # own progress rather than from its start, it lands in the same stretch of the run however
    # busy the machine is.
    rng = random.Random(f"{args.seed}/{name}/{k}")
    names = sorted(ref["snapshots"])
    after = names[rng.randrange(0, len(names) - 2)]
    fraction = rng.random()
    base = os.path.join(args.work, name, f"trial-{k:02d}")
    os.makedirs(base)
    killed_dir, finished = run_and_kill(args, scenario, base, after,
                                        fraction * ref["seconds"] / len(names))
    resumed_dir = os.path.join(base, "resumed")
    step, snapshot, temps = newest_snapshot(os.path.join(killed_dir, "snapshots"))
    out = {"trial": k, "after": after, "fraction": fraction, "finished": finished,
           "step": step, "mid_write": bool(temps)}  # only snapshots are written there
    if snapshot is None:
        raise RuntimeError(f"{name} trial {k}: no complete step snapshot after {after} appeared")
    got_step, got_hash = info(args.sable, snapshot, os.path.join(base, "info.log"))
    if got_step != step:
        raise RuntimeError(f"{name} trial {k}: {snapshot} holds step {got_step}")
    want_hash = reference_snapshot_hash(args, ref, os.path.basename(snapshot))
    if got_hash != want_hash:
        raise RuntimeError(f"{name} trial {k}: {snapshot} has state hash {got_hash}, the "
                           f"uninterrupted run's snapshot {want_hash}")
    status, text = run([args.sable, "run", scenario, "--resume", snapshot, "--out", resumed_dir,
                        "--threads", "1"], os.path.join(base, "resumed.log"))
    got = final_hash(status, text, f"{name} trial {k}: resume from {snapshot}")
    if got != ref["hash"]:
        raise RuntimeError(f"{name} trial {k}: resumed from {snapshot}, final state hash {got}, "
                           f"uninterrupted {ref['hash']}")
    shutil.rmtree(base)  # passed: keep only the failures' files
    return out


def reference(args, scenario, name):
    """The uninterrupted run: its final hash, wall time and step snapshots."""
    out_dir = os.path.join(args.work, name, "reference")
    t0 = time.monotonic()
    status, text = run([args.sable, "run", scenario, "--out", out_dir, "--threads", "1"],
                       os.path.join(args.work, name, "reference.log"))
    seconds = time.monotonic() - t0
    digest = final_hash(status, text, f"{name}: uninterrupted run")
    snaps = sorted(glob.glob(os.path.join(out_dir, "snapshots", "step_*.h5")))
    return {"hash": digest, "seconds": seconds, "dir": os.path.join(out_dir, "snapshots"),
            "snapshots": {os.path.basename(p): None for p in snaps}}


def reference_snapshot_hash(args, ref, name):
    """The state hash of the uninterrupted run's snapshot `name` (None if it has none)."""
    if name not in ref["snapshots"]:
        return None
    if ref["snapshots"][name] is None:
        path = os.path.join(ref["dir"], name)
        ref["snapshots"][name] = info(args.sable, path, path + ".info.log")[1]
    return ref["snapshots"][name]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sable", required=True)
    ap.add_argument("--work", required=True, help="scratch directory (emptied first)")
    ap.add_argument("--trials", type=int, default=10, help="per scenario")
    ap.add_argument("--seed", default="41")
    ap.add_argument("scenarios", nargs="+")
    args = ap.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    failures = 0
    t_start = time.monotonic()
    for scenario in args.scenarios:
        name = os.path.splitext(os.path.basename(scenario))[0]
        os.makedirs(os.path.join(args.work, name))
        ref = reference(args, scenario, name)
        print(f"{name}: uninterrupted run {ref['seconds']:.2f} s, {len(ref['snapshots'])} step "
              f"snapshots, state hash {ref['hash']}")
        done = []
        for k in range(args.trials):
            try:
                done.append(trial(args, scenario, name, ref, k))
            except RuntimeError as e:
                failures += 1
                print(f"FAIL: {e}")
        for t in done:
            where = "finished before the kill" if t["finished"] else "killed"
            print(f"  trial {t['trial']:2d}: {t['fraction']:.3f} of an interval after "
                  f"{t['after']}: {where}, newest snapshot step {t['step']}"
                  f"{', during a snapshot write' if t['mid_write'] else ''}")
        mid = sum(t["mid_write"] for t in done)
        late = sum(t["finished"] for t in done)
        print(f"{name}: {len(done)} of {args.trials} trials resumed to the reference hash; "
              f"{mid} killed during a snapshot write, {late} finished before the kill")
    print(f"total {time.monotonic() - t_start:.1f} s, {failures} failure(s)")
    if failures == 0:
        shutil.rmtree(args.work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
