#!/usr/bin/python3
"""The state hash of every example scenario, each cut short, for checking that a refactor
changes no bit.

    /usr/bin/python3 scripts/example_hashes.py SABLE OUT [--steps N] > hashes.txt

runs each `examples/**/*.toml` with the executable SABLE for at most N steps per stage
(default 20: `steps` and `max_steps` lowered to N, so every stage starts and the run passes
through each kind of stage, its walls, servos and wetting; SHORTER below lowers it further for
the scenarios whose steps are slow) into OUT/NAME, one thread, and
prints one line per scenario: its path and the state hash of its `done:` line ("FAILED" and
the exit status if it did not finish). Run it with the executable before and after a change,
then `diff` the two outputs: a refactor must leave every line alone. The cut copy of a
scenario is written beside it (a data file it names is relative to it) under a hidden name,
and removed.

    /usr/bin/python3 scripts/example_hashes.py SABLE OUT --expect tests/data/example_hashes.txt

compares instead with recorded lines (the test ExampleHashes: '#' starts a comment) and fails,
naming each scenario whose hash changed, is missing or is new.
"""
import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

HASH_RE = re.compile(r"^done: .*state hash ([0-9a-f]{16})\s*$", re.M)
STEPS_RE = re.compile(r"^(\s*(?:max_)?steps\s*=\s*)([0-9_]+)", re.M)


# Steps per stage for the scenarios whose steps are slow, so that the check stays a small part
# of CI: triaxial-cd's NLGS reaches its cap of 1,000 sweeps once the grains are packed (~3.5 s a
# step on one core, its header): 20 steps per stage took 334 s (one core, the other busy),
# 3 per stage take 0.3 s and still pass through its three stages, servos and solver.
SHORTER = {"examples/force-pdf/triaxial-cd.toml": 3}


def cut(text: str, steps: int) -> str:
    return STEPS_RE.sub(lambda m: m.group(1) + str(min(int(m.group(2).replace("_", "")), steps)),
                        text)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sable", help="the sable executable")
    ap.add_argument("out", help="output root (each scenario's run in OUT/NAME)")
    ap.add_argument("--steps", type=int, default=20, help="steps per stage at most (20)")
    ap.add_argument("--expect", help="recorded 'path hash' lines to compare with")
    a = ap.parse_args()
    expected = None
    if a.expect:
        expected = {}
        for line in Path(a.expect).read_text().splitlines():
            line = line.split("#", 1)[0].strip()
            if line:
                path, value = line.split()
                expected[path] = value
    got = {}
    root = Path(__file__).resolve().parent.parent
    failed = 0
    for scen in sorted((root / "examples").rglob("*.toml")):
        if scen.name.startswith("."):  # a cut copy left by a killed run of this script
            continue
        rel = scen.relative_to(root)
        copy = scen.with_name(".hashcheck-" + scen.name)
        out = Path(a.out) / str(rel.with_suffix("")).replace(os.sep, "__")
        try:
            copy.write_text(cut(scen.read_text(), min(a.steps, SHORTER.get(rel.as_posix(), a.steps))))
            r = subprocess.run([a.sable, "run", str(copy), "--out", str(out), "--overwrite",
                                "--threads", "1"], capture_output=True, text=True)
        finally:
            copy.unlink(missing_ok=True)
        m = HASH_RE.search(r.stdout + r.stderr)
        if r.returncode == 0 and m:
            print(f"{rel} {m.group(1)}", flush=True)
            got[str(rel)] = m.group(1)
        else:
            failed += 1
            print(f"{rel} FAILED (exit {r.returncode})", flush=True)
            sys.stderr.write((r.stdout + r.stderr)[-2000:])
    if expected is not None:
        for path in sorted(set(expected) | set(got)):
            if expected.get(path) != got.get(path):
                failed += 1
                print(f"{path}: hash {got.get(path, 'missing')}, recorded "
                      f"{expected.get(path, 'none')} ({a.expect})", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
