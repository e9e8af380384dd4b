"""Sable from Python: scenarios, simulations stepped from Python, numpy arrays, snapshots.

    import sable
    sim = sable.Simulation(sable.Scenario.load("examples/pour.toml"), out_dir="out/pour")
    sim.step(100)
    g = sim.grains()          # read-only numpy views: positions, velocities, radii, ...
    print(sim.time, g["positions"][:, 2].max(), sim.contacts()["normal_force"].mean())

The engine is the extension module sable._sable (apps/python/sable_module.cpp), the same
code as the `sable` command: a run from Python gives the CLI's bits. Tutorial: docs/python.md.
"""
import csv
import json
import os
import re
import tempfile

import numpy as np

from ._sable import (  # noqa: F401
    InputError,
    IoError,
    Scenario,
    Simulation,
    SimulationError,
    __version__,
    _analyze,
    load_snapshot,
)

__all__ = ["InputError", "IoError", "Scenario", "Simulation", "SimulationError",
           "__version__", "analyze", "load_snapshot"]


_PLACE = re.compile(r"^(?P<path>[^\n]+?):(?P<line>\d+):(?P<column>\d+): (?P<rest>.*)", re.S)
_KEY = re.compile(r"^(?:unknown key |missing required key )?(?P<key>[^\s=:;]+)")


def _place(error):
    """(path, line, column, key) of an InputError's message 'PATH:LINE:COL: KEY ...'; the
    parts a message has not got are None (a file that cannot be read: the path alone)."""
    text = str(error)
    m = _PLACE.match(text)
    if m is None:
        head = text.split(": ", 1)[0]
        return (head if ": " in text else None), None, None, None
    key = _KEY.match(m["rest"])
    return m["path"], int(m["line"]), int(m["column"]), key["key"] if key else None


InputError.path = property(lambda self: _place(self)[0], doc="the file the error is in")
InputError.line = property(lambda self: _place(self)[1], doc="its line (1-based), or None")
InputError.column = property(lambda self: _place(self)[2], doc="its column, or None")
InputError.key = property(lambda self: _place(self)[3], doc="the key (a.b.c), or None")


def _resume(path, scenario=None, **options):
    """A Simulation continuing snapshot `path` (as `sable run --resume`), under `scenario`
    (default: the one stored in the snapshot). Keywords as Simulation()."""
    if scenario is None:
        scenario = Scenario.from_snapshot(path)
    return Simulation(scenario, resume=os.fspath(path), **options)


Simulation.resume = staticmethod(_resume)


def _table(path):
    """A CSV written by `sable analyze` as {column: float array}, the CLI's digits parsed."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    columns = list(zip(*rows[1:])) if len(rows) > 1 else [()] * len(rows[0])
    out = {}
    for name, values in zip(rows[0], columns):
        try:
            out[name] = np.array(values, dtype=float)
        except ValueError:
            out[name] = np.array(values, dtype=object)
    return out


def analyze(source, out_dir=None, **options):
    """Run `sable analyze` on a snapshot path, a list of them, or a Simulation (saved first,
    into out_dir). Keywords: the CLI's options with _ for - (only=["forces", "fields"],
    grid="10x10x40", kernel="sphere", bins=50, ...).

    Returns {"dir": the output folder, "summary": summary.json as a dict, "tables": {name:
    {column: array}} for every CSV written}: the numbers the CLI writes, read back from its
    files (so the same to the last digit printed).
    """
    if isinstance(source, Simulation):
        out_dir = out_dir or tempfile.mkdtemp(prefix="sable-analysis-")
        os.makedirs(out_dir, exist_ok=True)
        snapshot = os.path.join(out_dir, f"step_{source.steps:010d}.h5")
        source.save(snapshot)
        snapshots = [snapshot]
    elif isinstance(source, (str, os.PathLike)):
        snapshots = [os.fspath(source)]
    else:
        snapshots = [os.fspath(s) for s in source]
    folder = _analyze(snapshots, os.fspath(out_dir) if out_dir else "", options)
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    tables = {name[:-4]: _table(os.path.join(folder, name))
              for name in sorted(os.listdir(folder)) if name.endswith(".csv")}
    return {"dir": folder, "summary": summary, "tables": tables}
