#!/usr/bin/env python3
"""The Python examples (examples/python) run, each well under 2 minutes, and say sane things.

- pour_live.py: the bed settles (kinetic energy below 1e-6 of its peak, the script's own
  stop) into a packing fraction between 0.45 and 0.64: no random packing of nearly equal
  spheres is denser than 0.64 (random close packing), and the lattice the grains start from
  is 0.24 (a bed still near that has not settled; a bed 3.5 diameters deep in a box 15 wide,
  walls and free surface included in the measure, sits well below 0.6);
- repose_sweep.py at mu = 0.1 and 0.7: both angles between 5 and 35 degrees (a heap, not a
  spread layer nor a column), the rougher one steeper (by more than the method's scatter of
  about 2 degrees, measured over the four default frictions);
- force_network.py on the pour's snapshot: a PNG, and more than a quarter of the contacts
  above the mean force carrying more than half of the total (a force network's strong
  part: Radjai et al. 1998 find about 40 % carrying most of the load).

usage: test_examples.py WORK_DIR
"""
import os
import re
import subprocess
import sys
import time
import unittest

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                        "python")
WORK = None


def run(script, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("DISPLAY", None)
    t0 = time.monotonic()
    r = subprocess.run(["/usr/bin/python3", os.path.join(EXAMPLES, script), *args], env=env,
                       check=True, capture_output=True, text=True, timeout=120)
    return r.stdout, time.monotonic() - t0


class Examples(unittest.TestCase):
    def test_pour_then_force_network(self):
        out = os.path.join(WORK, "pour")
        text, _ = run("pour_live.py", out)
        fraction = float(re.search(r"packing fraction ([0-9.]+)", text).group(1))
        self.assertTrue(0.45 < fraction < 0.64, text)
        self.assertTrue(os.path.exists(os.path.join(out, "kinetic_energy.png")))
        text, _ = run("force_network.py", os.path.join(out, "settled.h5"),
                      os.path.join(out, "forces.png"))
        m = re.search(r"([0-9.]+)% above the mean carrying ([0-9.]+)%", text)
        self.assertGreater(float(m.group(1)), 25.0, text)
        self.assertGreater(float(m.group(2)), 50.0, text)
        self.assertTrue(os.path.exists(os.path.join(out, "forces.png")))

    def test_repose_sweep(self):
        out = os.path.join(WORK, "repose")
        text, _ = run("repose_sweep.py", out, "0.1", "0.7")
        angles = [float(a) for a in re.findall(r"angle of repose ([0-9.]+) deg", text)]
        self.assertEqual(len(angles), 2, text)
        for a in angles:
            self.assertTrue(5.0 < a < 35.0, text)
        self.assertGreater(angles[1] - angles[0], 2.0, text)
        self.assertTrue(os.path.exists(os.path.join(out, "repose.png")))


if __name__ == "__main__":
    WORK = os.path.abspath(sys.argv[1])
    os.makedirs(WORK, exist_ok=True)
    unittest.main(argv=sys.argv[:1] + sys.argv[2:], verbosity=2)
