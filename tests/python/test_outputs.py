#!/usr/bin/env python3
"""A run's outputs read without Sable: VTK frames and XDMF sidecars against the snapshot.

VTK: the files read with xml + numpy (scripts/vtkxml.py).

One short DEM run (300 spheres settling in a box) per encoding of [output] vtk_format writes
its end-of-stage VTK frame and snapshot at the same step. Each frame's arrays must be the
snapshot's:
- binary and zlib store the doubles' bits: positions, radii, velocities, spins, forces and ids
  equal the snapshot's exactly (the reason for a raw format: nothing lost);
- ascii prints 9 significant digits: within 5e-9 relative (half a unit of the 9th digit),
  plus 1e-15 for the parse;
- the contacts file has one line per pair of the snapshot with a non-zero force, from grain i
  to grain j, with the pair's ids, and its normal force f . n within 1e-12 relative of the
  one numpy computes (the same three products, summed in another order; ascii adds its 5e-9);
- the walls' cells carry the walls' forces of the snapshot, bit for bit;
- binary is smaller than ascii, and zlib smaller than binary.
`sable analyze --only fields` then writes fields.vti in each encoding: its arrays equal the
fields.csv columns written beside it (the CSV prints 12 significant digits: 1e-11 relative,
plus an absolute 1e-300 for exact zeros).

XDMF (VtkAgainstSnapshot.test_xdmf_sidecars, for the 3D run and a 2D one): every snapshot
snapshots/NAME.h5 has its xdmf/NAME.xmf (and snapshots/ nothing else), whose every HDF
reference names, by a relative path, a dataset of that snapshot with the
declared dimensions, number type and byte size, whose grid has one vertex per grain, whose
time is the snapshot's to the bit, and whose id hyperslab selects column 0 of /particles/id.

usage: test_outputs.py SABLE_EXECUTABLE WORK_DIR
"""
import csv
import os
import shutil
import subprocess
import sys
import unittest
import xml.etree.ElementTree as ET

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "scripts"))
import vtkxml  # noqa: E402
from scenarios import box_2d, box_3d  # noqa: E402

SABLE = WORK = None
STEPS = 3000
SCENARIO = box_3d(7, """
[[stage]]
name = "settle"
steps = {steps}

[output]
dir = "{out}"
vtk_format = "{fmt}"
""")
FORMATS = ("binary", "zlib", "ascii")
SCENARIO_2D = box_2d("""
[[stage]]
name = "settle"
steps = 500

[output]
dir = "{out}"
snapshot_interval = 250
""")
XDMF_TYPES = {("Float", 8): "f8", ("UInt", 4): "u4", ("UInt", 2): "u2", ("UChar", 1): "u1"}


def run(fmt):
    out = os.path.join(WORK, fmt)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    path = os.path.join(WORK, f"{fmt}.toml")
    with open(path, "w") as f:
        f.write(SCENARIO.format(steps=STEPS, out=out, fmt=fmt))
    subprocess.run([SABLE, "run", path, "--threads", "1"], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    return out


class VtkAgainstSnapshot(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = {fmt: run(fmt) for fmt in FORMATS}

    def frame(self, fmt, kind):
        return vtkxml.read(os.path.join(self.out[fmt], "vtk", f"{kind}_{STEPS:010d}.vtp"))

    def snapshot(self, fmt):
        return h5py.File(os.path.join(self.out[fmt], "snapshots", "end_of_stage_1.h5"), "r")

    def same(self, fmt, got, want, what):
        got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
        self.assertEqual(got.shape, want.shape, what)
        if fmt == "ascii":
            np.testing.assert_allclose(got, want, rtol=5e-9 + 1e-15, atol=0, err_msg=what)
        else:
            self.assertTrue(np.array_equal(got, want), f"{fmt} {what}: not the snapshot's bits")

    def test_grains(self):
        for fmt in FORMATS:
            g, s = self.frame(fmt, "grains"), self.snapshot(fmt)
            p = s["particles"]
            self.assertEqual(g.formats, {"ascii"} if fmt == "ascii" else {"appended"})
            self.assertEqual(int(g.piece["NumberOfPoints"]), 300)
            self.same(fmt, g.points, p["x"][:], "positions")
            self.same(fmt, g.point_data["radius"], p["radius"][:], "radii")
            self.same(fmt, g.point_data["velocity"], p["v"][:], "velocities")
            self.same(fmt, g.point_data["angular_velocity"], p["w"][:], "spins")
            self.same(fmt, g.point_data["force"], p["f"][:], "forces")
            self.assertTrue(np.array_equal(g.point_data["id"], p["id"][:, 0]), fmt)
            self.assertEqual(g.point_data["id"].dtype, np.int64)
            self.assertEqual(g.point_data["fixed"].dtype, np.uint8)
            conn, offs = g.cells["Verts"]
            self.assertTrue(np.array_equal(conn, np.arange(300)))
            self.assertTrue(np.array_equal(offs, np.arange(1, 301)))

    def test_contacts(self):
        for fmt in FORMATS:
            c, s = self.frame(fmt, "contacts"), self.snapshot(fmt)
            pairs, x, ids = s["neighbors/pairs"], s["particles/x"][:], s["particles/id"][:, 0]
            force = pairs["force"][:]
            touching = np.flatnonzero((force != 0).any(axis=1))
            self.assertGreater(len(touching), 100, "the settled bed should have contacts")
            i, j = pairs["i"][:][touching], pairs["j"][:][touching]
            self.assertEqual(int(c.piece["NumberOfLines"]), len(touching))
            self.assertTrue(np.array_equal(c.cell_data["id_i"], ids[i]), fmt)
            self.assertTrue(np.array_equal(c.cell_data["id_j"], ids[j]), fmt)
            ends = c.points.reshape(-1, 2, 3)
            self.same(fmt, ends[:, 0], x[i], "contact start points")
            self.same(fmt, ends[:, 1], x[j], "contact end points")
            d = x[i] - x[j]
            n = d / np.linalg.norm(d, axis=1)[:, None]
            fn = (force[touching] * n).sum(axis=1)
            rtol = 1e-12 + (5e-9 if fmt == "ascii" else 0.0)
            np.testing.assert_allclose(c.cell_data["normal_force"], fn, rtol=rtol,
                                       atol=1e-12 * np.abs(fn).max())

    def test_walls(self):
        for fmt in FORMATS:
            w, s = self.frame(fmt, "walls"), self.snapshot(fmt)
            walls = w.cell_data["wall"]
            self.assertEqual(sorted(set(walls.tolist())), list(range(6)), "six box faces")
            self.same(fmt, w.cell_data["force"], s["walls/force"][:][walls], "wall forces")

    def test_sizes(self):
        size = {fmt: os.path.getsize(os.path.join(self.out[fmt], "vtk",
                                                  f"grains_{STEPS:010d}.vtp"))
                for fmt in FORMATS}
        self.assertLess(size["binary"], size["ascii"])
        self.assertLess(size["zlib"], size["binary"])

    def test_fields_vti(self):
        snap = os.path.join(self.out["binary"], "snapshots", "end_of_stage_1.h5")
        for fmt in FORMATS:
            an = os.path.join(WORK, f"fields-{fmt}")
            subprocess.run([SABLE, "analyze", snap, "--only", "fields", "--grid", "3x3x4",
                            "--vtk-format", fmt, "--out", an], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            f = vtkxml.read(os.path.join(an, "fields.vti"))
            self.assertEqual(f.type, "ImageData")
            self.assertEqual(f.image["WholeExtent"], "0 2 0 2 0 3")
            with open(os.path.join(an, "fields.csv")) as t:
                rows = list(csv.DictReader(t))
            self.assertEqual(len(rows), 36)
            for name, column in (("pressure", "pressure_Pa"), ("density", "density_kg_m3"),
                                 ("volume_fraction", "volume_fraction")):
                want = np.array([float(r[column]) for r in rows])
                np.testing.assert_allclose(f.point_data[name], want, rtol=1e-11, atol=1e-300,
                                           err_msg=f"{fmt} {name}")
            stress = f.point_data["stress"]
            self.assertEqual(stress.shape, (36, 9))
            want = np.array([float(r["sigma_zz_Pa"]) for r in rows])
            np.testing.assert_allclose(stress[:, 8], want, rtol=1e-11, atol=1e-300)

    def check_sidecar(self, xmf, snapshot):
        folder = os.path.dirname(xmf)
        h5 = h5py.File(snapshot, "r")
        n = int(h5["particles/x"].shape[0])
        grid = ET.parse(xmf).getroot().find("Domain/Grid")
        self.assertEqual(float(grid.find("Time").get("Value")), h5.attrs["time"], xmf)
        topo = grid.find("Topology")
        self.assertEqual(topo.get("TopologyType"), "Polyvertex")
        self.assertEqual(int(topo.get("NumberOfElements")), n)
        dim = int(h5.attrs["dimension"])
        self.assertEqual(grid.find("Geometry").get("GeometryType"), "XYZ" if dim == 3 else "XY")
        items = grid.findall(".//DataItem[@Format='HDF']")
        self.assertEqual(len(items), 9, "geometry and eight attributes")
        for item in items:
            name, dataset = item.text.split(":")
            self.assertEqual(os.path.normpath(os.path.join(folder, name)),
                             os.path.normpath(snapshot), "its own snapshot, by a relative path")
            data = h5[dataset]
            dims = tuple(int(v) for v in item.get("Dimensions").split())
            self.assertEqual(tuple(data.shape) if data.ndim > 1 and data.shape[1] > 1
                             else (data.shape[0],), dims, dataset)
            want = XDMF_TYPES[(item.get("NumberType"), int(item.get("Precision")))]
            self.assertEqual(data.dtype.str.lstrip("<|"), want, dataset)
        slab = grid.find(".//DataItem[@ItemType='HyperSlab']")
        start, stride, count = np.array(slab.find("DataItem[@Format='XML']").text.split(),
                                        dtype=int).reshape(3, 2)
        self.assertEqual(list(start), [0, 0], "from row 0, column 0 (the id's index)")
        self.assertEqual(list(stride), [1, 1])
        self.assertEqual(list(count), [n, 1], "every grain, one column")
        return n

    def sidecar_of(self, out, name):
        return self.check_sidecar(os.path.join(out, "xdmf", name + ".xmf"),
                                  os.path.join(out, "snapshots", name + ".h5"))

    def test_xdmf_sidecars(self):
        self.assertEqual(self.sidecar_of(self.out["binary"], "end_of_stage_1"), 300)
        out2 = os.path.join(WORK, "two-d")
        shutil.rmtree(out2, ignore_errors=True)
        path = os.path.join(WORK, "two-d.toml")
        with open(path, "w") as f:
            f.write(SCENARIO_2D.format(out=out2))
        subprocess.run([SABLE, "run", path], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        # snapshots/ holds snapshots only (scripts and tests list it); xdmf/ one sidecar each.
        names = ["end_of_stage_1", "step_0000000250", "step_0000000500"]
        self.assertEqual(sorted(os.listdir(os.path.join(out2, "snapshots"))),
                         [n + ".h5" for n in names])
        self.assertEqual(sorted(os.listdir(os.path.join(out2, "xdmf"))),
                         [n + ".xmf" for n in names])
        for name in names:
            self.assertEqual(self.sidecar_of(out2, name), 60)

    def test_bad_format_is_refused(self):
        path = os.path.join(WORK, "bad.toml")
        with open(path, "w") as f:
            f.write(SCENARIO.format(steps=1, out=os.path.join(WORK, "bad"), fmt="hdf5"))
        r = subprocess.run([SABLE, "run", path], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("vtk_format", r.stderr)
        self.assertIn("binary", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(WORK, "bad")), "nothing written")


if __name__ == "__main__":
    SABLE, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    os.makedirs(WORK, exist_ok=True)
    unittest.main(argv=sys.argv[:1] + sys.argv[3:], verbosity=2)
