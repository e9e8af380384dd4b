#!/usr/bin/env python3
"""`import sable` against the `sable` command: the same runs, bit for bit.

Every check is exact unless said: a Simulation is the object `sable run` drives
(src/sable/scenario/simulation.hpp), so a run from Python must give the CLI's state hash and
the CLI's arrays to the last bit, however it is stepped (one call, stage by stage, chunks of
steps); the module's arrays must be the snapshot's datasets; sable.analyze must write the
CLI's files byte for byte. Run by ctest with PYTHONPATH at the build's python/ folder.

usage: test_module.py SABLE_EXECUTABLE WORK_DIR
"""
import filecmp
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
import unittest

import h5py
import numpy as np

import sable
from scenarios import box_2d, box_3d

SABLE = WORK = None
# A fall, then the box's +x face pushed in: two stages, a moving wall.
SCENARIO = box_3d(11, """
[[stage]]
name = "fall"
steps = {fall}

[[stage]]
name = "push"
steps = 400
wall_velocity = {{ "box.xhi" = [-0.05, 0, 0] }}

[output]
dir = "out"
csv_interval = 100
""")
SCENARIO_2D = box_2d("""
[[stage]]
name = "settle"
steps = 700
""")


def scenario_file(name, text):
    path = os.path.join(WORK, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def cli_run(path, out):
    shutil.rmtree(out, ignore_errors=True)
    r = subprocess.run([SABLE, "run", path, "--out", out, "--threads", "1"], check=True,
                       capture_output=True, text=True)
    return int(re.search(r"state hash ([0-9a-f]{16})", r.stderr).group(1), 16)


class Module(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.toml = scenario_file("s.toml", SCENARIO.format(fall=1600))
        cls.cli_out = os.path.join(WORK, "cli")
        cls.cli_hash = cli_run(cls.toml, cls.cli_out)

    def sim(self, name, **kw):
        out = os.path.join(WORK, name)
        shutil.rmtree(out, ignore_errors=True)
        return sable.Simulation(sable.Scenario.load(self.toml), out_dir=out, threads=1, **kw)

    def test_version(self):
        self.assertRegex(sable.__version__, r"^\d+\.\d+\.\d+$")

    def test_scenario_errors_name_the_place(self):
        with self.assertRaises(sable.InputError) as e:
            sable.Scenario.from_string("[simulation]\ndimension = 3\nsolver = \"md\"\n",
                                       path="bad.toml")
        self.assertIn("bad.toml:3", str(e.exception))
        self.assertIn("solver", str(e.exception))
        self.assertIsInstance(e.exception, ValueError)
        x = e.exception
        self.assertEqual((x.path, x.line, x.column, x.key), ("bad.toml", 3, 10, "simulation.solver"))
        with self.assertRaises(sable.InputError) as e:
            sable.Scenario.from_string("[simulation]\ndimension = 3\nfoo = 1\n", path="k.toml")
        self.assertEqual((e.exception.line, e.exception.key), (3, "simulation.foo"))
        with self.assertRaises(sable.InputError) as e:
            sable.Scenario.load(os.path.join(WORK, "missing.toml"))
        self.assertIn("missing.toml", str(e.exception))
        self.assertEqual(e.exception.path, os.path.join(WORK, "missing.toml"))
        self.assertIsNone(e.exception.line)
        sc = sable.Scenario.load(self.toml)
        self.assertEqual((sc.dimension, sc.solver, sc.stages), (3, "dem", ["fall", "push"]))

    def test_same_hash_as_the_cli_however_stepped(self):
        one = self.sim("py-run")
        result = one.run()
        self.assertEqual(result["state_hash"], self.cli_hash)
        self.assertEqual(result["steps"], 2000)
        self.assertTrue(one.finished)
        staged = self.sim("py-stages")
        self.assertEqual(staged.run_stage(), 1600)
        self.assertEqual(staged.stage, 1)
        self.assertTrue(os.path.exists(os.path.join(WORK, "py-stages", "snapshots",
                                                    "end_of_stage_1.h5")), "stage end written")
        self.assertEqual(staged.run_stage(), 400)
        self.assertEqual(staged.state_hash, self.cli_hash)
        chunks = self.sim("py-chunks", outputs=False)
        taken = 0
        while not chunks.finished:
            taken += chunks.step(333)
        self.assertEqual(taken, 2000)
        self.assertEqual(chunks.step(5), 0, "nothing left")
        self.assertEqual(chunks.state_hash, self.cli_hash)
        # The CLI's outputs and the module's are the same files.
        for name in ("series.csv", "vtk/grains_0000002000.vtp", "vtk/contacts_0000001600.vtp"):
            self.assertTrue(filecmp.cmp(os.path.join(self.cli_out, name),
                                        os.path.join(WORK, "py-run", name), shallow=False), name)

    def test_arrays_are_the_snapshots(self):
        sim = self.sim("py-arrays")
        sim.run()
        g = sim.grains()
        with h5py.File(os.path.join(self.cli_out, "snapshots", "end_of_stage_2.h5"), "r") as s:
            p = s["particles"]
            for key, dataset in (("positions", "x"), ("velocities", "v"), ("forces", "f"),
                                 ("angular_velocities", "w"), ("torques", "t"),
                                 ("radii", "radius"), ("masses", "mass")):
                self.assertEqual(g[key].dtype, np.float64, key)
                self.assertEqual(g[key].shape, p[dataset].shape, key)
                self.assertTrue(np.array_equal(g[key], p[dataset][:]), key)
                self.assertFalse(g[key].flags.writeable, key)
            self.assertTrue(np.array_equal(g["ids"], p["id"][:, 0]))
            self.assertEqual(g["ids"].dtype, np.uint32)
            self.assertFalse(g["ids"].flags.writeable)
            pairs = s["neighbors/pairs"]
            touching = (pairs["force"][:] != 0).any(axis=1)
            c = sim.contacts()
            self.assertEqual(len(c["normal_force"]), touching.sum())
            self.assertTrue(np.array_equal(c["force"], pairs["force"][:][touching]))
            self.assertTrue(np.array_equal(c["id_i"], p["id"][:, 0][pairs["i"][:][touching]]))
            # f = (f.n) n + f_t: each component rounded twice (the product, the difference).
            f = c["force"]
            rebuilt = c["normal_force"][:, None] * c["normal"] + c["tangential_force"]
            self.assertLessEqual(np.abs(rebuilt - f).max(), 4 * np.finfo(float).eps *
                                 np.abs(f).max())
            self.assertTrue((np.abs((c["tangential_force"] * c["normal"]).sum(axis=1)) <=
                             4 * np.finfo(float).eps * np.abs(f).max()).all(), "in the plane")
            w = sim.walls()
            self.assertEqual(w["names"], [n.decode() for n in s["walls/names"][:]])
            self.assertTrue(np.array_equal(w["force"], s["walls/force"][:]))
            self.assertTrue(np.array_equal(w["orientation"], s["walls/orientation"][:]))
        info = subprocess.run([SABLE, "info", os.path.join(self.cli_out, "snapshots",
                                                           "end_of_stage_2.h5")],
                              check=True, capture_output=True, text=True).stdout
        self.assertRegex(info, rf"grains\s+{len(g['radii'])}\n")
        self.assertRegex(info, rf"state hash\s+{sim.state_hash:016x}\n")

    def test_run_to_a_named_stage(self):
        sim = self.sim("py-named", outputs=False)
        with self.assertRaises(sable.InputError) as e:
            sim.run_stage("lift")
        self.assertIn("fall, push", str(e.exception), "the message lists the stages")
        self.assertEqual(sim.run_stage("push"), 2000, "the stages before it run too")
        self.assertEqual(sim.state_hash, self.cli_hash)
        with self.assertRaises(sable.InputError):
            sim.run_stage("fall")  # has ended

    def test_wall_rotation_and_stress_between_steps(self):
        sim = self.sim("py-turn", outputs=False)
        sim.step(10)
        p = sim.walls()["point"][0]  # box.xlo
        sim.set_wall_rotation("box.xlo", p, [1.0, 0.0, 0.0], 2.0)
        sim.step(50)
        w, x = sim.walls()["orientation"][0][:2]
        # The turn about x by rate x time, composed step by step: 1e-9 relative covers the
        # round-off of 50 compositions of unit quaternions by far.
        self.assertAlmostEqual(2 * np.arctan2(x, w), 2.0 * 50 * sim.dt,
                               delta=1e-9 * 2.0 * 50 * sim.dt)
        # A stress target on the lid, far above the grains: the servo moves it into them
        # (too little stress: the wall advances, loading/servo.hpp).
        with self.assertRaises(sable.InputError) as e:
            sim.set_wall_stress("box.zhi", 50.0)  # this stage has no servo_max_velocity
        self.assertIn("max_velocity", str(e.exception))
        sim.set_wall_stress("box.zhi", 50.0, max_velocity=0.01)
        sim.step(1)
        # Its gain is max_velocity / target (the default): -50 Pa of error asks -0.01 m/s,
        # up to the rounding of that quotient and product (2 ulps).
        self.assertAlmostEqual(sim.walls()["velocity"][5, 2], -0.01, delta=2 * np.spacing(0.01))
        with self.assertRaises(sable.InputError):
            sim.set_wall_stress("lid", 50.0)

    def test_views_follow_the_simulation(self):
        sim = self.sim("py-views", outputs=False)
        sim.step(10)
        x = sim.grains()["positions"]
        before = np.array(x)
        sim.step(10)
        self.assertFalse(np.array_equal(x, before), "a view shows the current state")

    def test_snapshot_round_trip_and_resume(self):
        sim = self.sim("py-save")
        sim.step(1000)
        mid = os.path.join(WORK, "py-save", "mid.h5")
        sim.save(mid)
        self.assertTrue(os.path.exists(mid[:-3] + ".xmf"))
        snap = sable.load_snapshot(mid)
        g = sim.grains()
        for key in ("positions", "velocities", "angular_velocities", "radii", "ids"):
            self.assertTrue(np.array_equal(snap[key], g[key]), key)
        self.assertEqual((snap["step"], snap["state_hash"]), (1000, sim.state_hash))
        shutil.rmtree(os.path.join(WORK, "py-resumed"), ignore_errors=True)
        resumed = sable.Simulation.resume(mid, out_dir=os.path.join(WORK, "py-resumed"),
                                          threads=1)
        self.assertEqual(resumed.run()["state_hash"], self.cli_hash)

    def test_analyses_are_the_clis(self):
        snap = os.path.join(self.cli_out, "snapshots", "end_of_stage_2.h5")
        cli = os.path.join(WORK, "an-cli")
        shutil.rmtree(cli, ignore_errors=True)
        subprocess.run([SABLE, "analyze", snap, "--out", cli, "--only", "forces,fabric,stress",
                        "--bins", "20"], check=True, capture_output=True)
        py = sable.analyze(snap, out_dir=os.path.join(WORK, "an-py"),
                           only=["forces", "fabric", "stress"], bins=20)
        names = sorted(n for n in os.listdir(cli) if n.endswith(".csv"))
        self.assertEqual(sorted(n + ".csv" for n in py["tables"]), names)
        for name in names:
            self.assertTrue(filecmp.cmp(os.path.join(cli, name), os.path.join(py["dir"], name),
                                        shallow=False), name)
        pdf = py["tables"]["force_pdf_compressive"]
        self.assertTrue(all(isinstance(v, np.ndarray) for v in pdf.values()))
        self.assertIn("forces", py["summary"])
        with self.assertRaises(sable.InputError):
            sable.analyze(snap, out_dir=os.path.join(WORK, "an-bad"), bins_count=3)

    def test_two_dimensions(self):
        path = scenario_file("two.toml", SCENARIO_2D.format())
        cli = cli_run(path, os.path.join(WORK, "two-cli"))
        sim = sable.Simulation(sable.Scenario.load(path), outputs=False, threads=1)
        sim.run()
        self.assertEqual(sim.state_hash, cli)
        g = sim.grains()
        self.assertEqual(g["positions"].shape, (60, 2))
        self.assertEqual(g["angular_velocities"].shape, (60,))
        self.assertEqual(sim.walls()["force"].shape, (4, 2))

    def test_wall_control_between_steps(self):
        sim = self.sim("py-walls", outputs=False)
        sim.step(10)
        z0 = sim.walls()["point"][5, 2]  # box.zhi
        sim.set_wall_velocity("box.zhi", [0.0, 0.0, -0.01])
        sim.step(100)
        # 100 steps of dt at -0.01 m/s, added to the position step by step: each addition
        # rounds by at most half an ulp of the position, so 100 ulps bound the difference.
        moved = sim.walls()["point"][5, 2] - z0
        self.assertAlmostEqual(moved, -0.01 * 100 * sim.dt, delta=100 * np.spacing(z0))
        with self.assertRaises(sable.InputError) as e:
            sim.set_wall_velocity("lid", [0.0, 0.0, 0.0])
        self.assertIn("box.zhi", str(e.exception), "the message lists the walls")
        with self.assertRaises(sable.InputError):
            sim.set_wall_velocity("box.zhi", [0.0, 1.0])  # 2 numbers in 3D

    def test_ctrl_c_stops_at_a_complete_step_and_the_gil_is_released(self):
        path = scenario_file("long.toml", SCENARIO.format(fall=10_000_000))
        sim = sable.Simulation(sable.Scenario.load(path), outputs=False, threads=1)
        ticks = []
        stop = threading.Event()

        def tick():  # runs only if the stepping thread lets go of the GIL
            while not stop.is_set():
                ticks.append(time.monotonic())
                time.sleep(0.01)

        ticker = threading.Thread(target=tick)
        ticker.start()
        timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
        timer.start()
        t0 = time.monotonic()
        with self.assertRaises(KeyboardInterrupt):
            sim.run()
        stop.set()
        ticker.join()
        elapsed = time.monotonic() - t0
        self.assertLess(elapsed, 5.0, "Ctrl-C answered")
        self.assertGreater(sum(1 for t in ticks if t0 < t < t0 + elapsed), 10,
                           "another thread ran while the simulation stepped")
        steps = sim.steps
        self.assertGreater(steps, 0)
        self.assertEqual(sim.step(3), 3, "the simulation goes on")
        self.assertEqual(sim.steps, steps + 3)


if __name__ == "__main__":
    SABLE, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    os.makedirs(WORK, exist_ok=True)
    unittest.main(argv=sys.argv[:1] + sys.argv[3:], verbosity=2)
