"""`mpirun -np N sable run` against `sable run`: the same state hash, the same series.csv
byte for byte, snapshots (written by the processes together, parallel HDF5) holding the serial
run's every dataset and attribute bit for bit, snapshots that resume on any number of processes with the serial run's end
state, a failed grain stopping every process at the serial run's step, and a refusal (exit 2,
the key named) for what does not run decomposed.

Usage: run_check.py SABLE MPIEXEC WORKDIR SCENARIO CD_SCENARIO [MORE_SCENARIO ...]
(each further scenario: its hash, series.csv and snapshots on 2, 3 and 4 processes against
the serial run's, and its first step_*.h5 snapshot of 4 processes resumed on 3)

The promise (docs/ARCHITECTURE.md, "Domain decomposition"): one global order of every sum, so
the bits of a serial run for any number of processes. Every comparison here is exact: a
single bit apart fails.
"""
import filecmp
import os

import h5py
import numpy
import re
import shutil
import subprocess
import sys

SABLE, MPIEXEC, WORK, SCENARIO, CD_SCENARIO = sys.argv[1:6]
MORE = sys.argv[6:]
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1")
failures = []


def run(np, args, expect_rc=0):
    cmd = ([MPIEXEC, "-np", str(np), "--oversubscribe"] if np else []) + [SABLE] + args
    p = subprocess.run(cmd, env=ENV, capture_output=True, text=True, timeout=600)
    if p.returncode != expect_rc:
        sys.exit(f"{' '.join(cmd)}: exit {p.returncode}, expected {expect_rc}\n{p.stderr}")
    return p.stderr


def final_hash(log):
    m = re.findall(r"state hash ([0-9a-f]{16})", log)
    if not m:
        sys.exit(f"no state hash in the log:\n{log}")
    return m[-1]


def h5_items(path):
    """Every dataset (dtype, shape, raw bytes) and attribute of an HDF5 file, by path."""
    items = {}

    def visit(name, obj):
        for key, value in obj.attrs.items():
            items[f"{name}@{key}"] = numpy.asarray(value).tobytes()
        if isinstance(obj, h5py.Dataset):
            value = obj[()]
            items[name] = (str(obj.dtype), obj.shape, numpy.asarray(value).tobytes())

    with h5py.File(path, "r") as f:
        visit("/", f)
        f.visititems(visit)
    return items


def same_snapshots(dir_a, dir_b):
    """The names of the snapshots of dir_b whose contents differ from dir_a's (or are missing)."""
    differ = []
    for name in sorted(os.listdir(os.path.join(dir_a, "snapshots"))):
        a, b = (os.path.join(d, "snapshots", name) for d in (dir_a, dir_b))
        ia, ib = h5_items(a), h5_items(b) if os.path.exists(b) else {}
        bad = sorted(k for k in set(ia) | set(ib) if ia.get(k) != ib.get(k))
        if bad:
            differ.append(f"{name}: {', '.join(bad[:5])}")
    return differ


def check(what, ok):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
out = {np: os.path.join(WORK, f"np{np}") for np in (0, 2, 3, 4)}
serial_log = run(0, ["run", SCENARIO, "--out", out[0]])
serial = final_hash(serial_log)
STAGE_LINE = r"stage \d+ '\w+' begins at step \d+"
print(f"serial: state hash {serial}")
for np in (2, 3, 4):
    log = run(np, ["run", SCENARIO, "--out", out[np]])
    h = final_hash(log)
    check(f"{np} processes: state hash {h} (serial {serial})", h == serial)
    check(f"{np} processes: series.csv identical to the serial run's",
          filecmp.cmp(os.path.join(out[0], "series.csv"), os.path.join(out[np], "series.csv"),
                      shallow=False))
    mine = sorted(os.listdir(os.path.join(out[np], "snapshots")))
    check(f"{np} processes: the same snapshots ({len(mine)})",
          mine == sorted(os.listdir(os.path.join(out[0], "snapshots"))))
    differ = same_snapshots(out[0], out[np])
    check(f"{np} processes: every snapshot's datasets and attributes the serial run's "
          f"({differ or 'all equal'})", not differ)
    stages = re.findall(STAGE_LINE, log)
    check(f"{np} processes: the stages begin at the serial run's steps ({stages})",
          len(stages) == 2 and stages == re.findall(STAGE_LINE, serial_log))

# Hybrid: 2 processes of 2 OpenMP threads each.
h = final_hash(run(2, ["run", SCENARIO, "--threads", "2", "--out", os.path.join(WORK, "hybrid")]))
check(f"2 processes x 2 threads: state hash {h} (serial {serial})", h == serial)

# A snapshot written by 4 processes, taken in the middle of the run, resumed on 1 and on 3.
snaps = sorted(f for f in os.listdir(os.path.join(out[4], "snapshots")) if f.startswith("step_"))
if not snaps:
    sys.exit("the scenario writes no step_*.h5 snapshot to resume from")
start = os.path.join(out[4], "snapshots", snaps[0])
for np in (0, 3):
    h = final_hash(run(np, ["run", SCENARIO, "--resume", start, "--out",
                            os.path.join(WORK, f"resume-np{np}")]))
    check(f"{snaps[0]} of 4 processes resumed on {max(np, 1)}: state hash {h} "
          f"(serial {serial})", h == serial)
# And the reverse: the serial run's snapshot resumed on 4 processes.
h = final_hash(run(4, ["run", SCENARIO, "--resume", os.path.join(out[0], "snapshots", snaps[0]),
                       "--out", os.path.join(WORK, "resume-serial-np4")]))
check(f"{snaps[0]} of the serial run resumed on 4 processes: state hash {h} (serial {serial})",
      h == serial)

for k, scenario in enumerate(MORE):
    name = os.path.basename(scenario)
    dirs = {np: os.path.join(WORK, f"more{k}-np{np}") for np in (0, 2, 3, 4)}
    h0 = final_hash(run(0, ["run", scenario, "--out", dirs[0]]))
    for np in (2, 3, 4):
        h = final_hash(run(np, ["run", scenario, "--out", dirs[np]]))
        check(f"{name} on {np} processes: state hash {h} (serial {h0})", h == h0)
        check(f"{name} on {np} processes: series.csv identical to the serial run's",
              filecmp.cmp(os.path.join(dirs[0], "series.csv"),
                          os.path.join(dirs[np], "series.csv"), shallow=False))
        if os.path.isdir(os.path.join(dirs[0], "snapshots")):
            differ = same_snapshots(dirs[0], dirs[np])
            check(f"{name} on {np} processes: snapshots bit for bit the serial run's "
                  f"({differ or 'all equal'})", not differ)
    snap_dir = os.path.join(dirs[4], "snapshots")
    steps = sorted(f for f in os.listdir(snap_dir) if f.startswith("step_")) \
        if os.path.isdir(snap_dir) else []
    if steps:
        h = final_hash(run(3, ["run", scenario, "--resume", os.path.join(snap_dir, steps[0]),
                               "--out", os.path.join(WORK, f"more{k}-resume")]))
        check(f"{name}: {steps[0]} of 4 processes resumed on 3: state hash {h} (serial {h0})",
              h == h0)

# A grain that fails its check on one process (here: faster than max_speed = 0.05 m/s, which
# the falling grains pass within ~5 ms) stops every process at the serial run's step, with the
# crash snapshot and exit 1.
runaway = os.path.join(WORK, "runaway.toml")
with open(SCENARIO) as f:
    text = f.read().replace("[simulation]\n", "[simulation]\nmax_speed = 0.05\n", 1)
with open(runaway, "w") as f:
    f.write(text)
crash = {}
for np in (0, 2):
    out_dir = os.path.join(WORK, f"runaway-np{np}")
    log = run(np, ["run", runaway, "--out", out_dir], expect_rc=1)
    crash[np] = sorted(f for f in os.listdir(os.path.join(out_dir, "snapshots"))
                       if f.startswith("crash_step_"))
    check(f"runaway grain on {max(np, 1)} process(es): the message names it",
          "max_speed" in log and "grain" in log)
check(f"runaway grain on 2 processes: the crash snapshot of the serial run's step ({crash[0]})",
      len(crash[0]) == 1 and crash[2] == crash[0])

# Contact dynamics is not decomposed: refused before anything is written, the key named.
log = run(2, ["run", CD_SCENARIO, "--out", os.path.join(WORK, "cd")], expect_rc=2)
check("contact dynamics on 2 processes: refused naming solver = \"cd\"",
      'solver = "cd"' in log and "one process" in log)
check("contact dynamics on 2 processes: nothing written",
      not os.path.exists(os.path.join(WORK, "cd")))

# The liquid of ruptured bridges counted as lost is one running sum: refused on several
# processes, naming the key.
wet = [m for m in MORE if "water_content" in open(m).read()]
if wet:
    lost = os.path.join(WORK, "lost.toml")
    with open(wet[0]) as f:
        text = f.read().replace('cohesion = "capillary"\n',
                                'cohesion = "capillary"\nruptured_liquid = "lost"\n', 1)
    with open(lost, "w") as f:
        f.write(text)
    log = run(2, ["run", lost, "--out", os.path.join(WORK, "lost")], expect_rc=2)
    check('ruptured_liquid = "lost" on 2 processes: refused naming the key',
          'ruptured_liquid = "lost"' in log and not os.path.exists(os.path.join(WORK, "lost")))

if failures:
    sys.exit(f"{len(failures)} check(s) failed")
