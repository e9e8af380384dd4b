#!/usr/bin/python3
"""Check that every include between Sable's modules points down a layer.

    /usr/bin/python3 scripts/check_layers.py

Reads the `#include "sable/MODULE/..."` lines of src/sable/ and apps/, and fails (exit 1,
naming the file, the line and the two layers) when a file includes a module of its own layer
or above, other than its own module. The layers, bottom to top (docs/ARCHITECTURE.md,
"Layers"):

    core < geometry < collision, generation < contact < world < loading, io, mpi
         < dem, cd, analysis < scenario < apps

so io and analysis read the world, never a solver, and nothing below the scenario knows a
scenario file. KNOWN lists the includes that still point up, each with its reason; the check
fails too when one of them is gone, so that the list shrinks with the code.
"""
import re
import sys
from pathlib import Path

LAYER = {
    "core": 0,
    "geometry": 1,
    "generation": 2,
    "collision": 2,
    "contact": 3,
    "world": 4,
    "loading": 5,
    "io": 5,
    "mpi": 5,
    "dem": 6,
    "cd": 6,
    "analysis": 6,
    "scenario": 7,
    "apps": 8,
}

# (file, included header): includes that point up, still to be removed.
KNOWN: set = set()

INCLUDE = re.compile(r'^\s*#\s*include\s+"(sable/([a-z_]+)/[^"]+)"')


def module_of(path: Path, root: Path) -> str:
    rel = path.relative_to(root).parts
    return "apps" if rel[0] == "apps" else rel[2]


def main() -> int:
    root = Path(__file__).resolve().parent.parent
    files = sorted(p for d in ("src/sable", "apps") for p in (root / d).rglob("*")
                   if p.suffix in (".hpp", ".cpp"))
    bad, seen = [], set()
    for f in files:
        mod = module_of(f, root)
        if mod not in LAYER:
            bad.append(f"{f.relative_to(root)}: module '{mod}' has no layer in {__file__}")
            continue
        for n, line in enumerate(f.read_text().splitlines(), 1):
            m = INCLUDE.match(line)
            if not m or m.group(2) == mod:
                continue
            dep, rel = m.group(2), str(f.relative_to(root))
            if dep not in LAYER:
                bad.append(f"{rel}:{n}: includes '{m.group(1)}' of an unknown module '{dep}'")
            elif LAYER[dep] >= LAYER[mod]:
                if (rel, m.group(1)) in KNOWN:
                    seen.add((rel, m.group(1)))
                    continue
                bad.append(f"{rel}:{n}: {mod} (layer {LAYER[mod]}) includes {m.group(1)} "
                           f"({dep}, layer {LAYER[dep]}): includes must point down")
    for k in sorted(KNOWN - seen):
        bad.append(f"{k[0]} no longer includes {k[1]}: remove it from KNOWN in {__file__}")
    for b in bad:
        print(b, file=sys.stderr)
    print(f"check_layers: {len(files)} files, {len(bad)} problem(s)"
          + (f", {len(KNOWN)} known upward include(s)" if KNOWN else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
