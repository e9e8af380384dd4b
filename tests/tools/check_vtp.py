#!/usr/bin/env python3
"""Structural check of a VTK XML PolyData (.vtp) or collection (.pvd) file written by Sable.

Reads the file with scripts/vtkxml.py (ASCII, raw appended or zlib-compressed arrays) and
checks that every DataArray has as many values as its section declares (PointData:
NumberOfPoints tuples, CellData: one tuple per cell, Points: 3 per point), that the cell
connectivity/offsets are consistent and index existing points, that the values are finite,
and optionally that the counts, array names and encoding are the expected ones. Exit status 0
when the file is well-formed, 1 (with the reason on stderr) otherwise.

usage: check_vtp.py FILE.vtp [--points N] [--cells N] [--arrays name,name,...]
                             [--format ascii|binary|zlib]
       check_vtp.py FILE.pvd --datasets N
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "scripts"))
import vtkxml  # noqa: E402

CELL_ATTRS = {"Verts": "NumberOfVerts", "Lines": "NumberOfLines", "Strips": "NumberOfStrips",
              "Polys": "NumberOfPolys"}


def fail(msg):
    print(f"check_vtp: {msg}", file=sys.stderr)
    sys.exit(1)


def check_arrays(f, arrays, tuples, where):
    for name, values in arrays.items():
        comps = f.components[name]
        if values.size != tuples * comps:
            fail(f"{where} array {name}: {values.size} values, expected {tuples} x {comps}")
        if values.dtype.kind == "f" and not np.isfinite(values).all():
            fail(f"array {name} has non-finite values")
    return list(arrays)


def encoding(f):
    if "appended" not in f.formats:
        return "ascii"
    return "zlib" if f.attrs.get("compressor") else "binary"


def check_piece(f, args):
    npts = int(f.piece["NumberOfPoints"])
    ncells = 0
    for tag, attr in CELL_ATTRS.items():
        declared = int(f.piece.get(attr, "0"))
        ncells += declared
        if tag not in f.cells:
            if declared:
                fail(f"{attr}={declared} but no <{tag}> section")
            continue
        conn, offs = f.cells[tag]
        if conn is None or offs is None:
            fail(f"<{tag}> lacks connectivity or offsets")
        if len(offs) != declared:
            fail(f"<{tag}>: {len(offs)} offsets for {attr}={declared}")
        if len(offs) and (offs[-1] != len(conn) or (np.diff(offs) < 0).any()):
            fail(f"<{tag}>: offsets do not partition the connectivity")
        if len(conn) and (conn.min() < 0 or conn.max() >= npts):
            fail(f"<{tag}>: connectivity indexes a missing point")
    if f.points is None:
        fail("no <Points> section")
    if f.components.get("Points") != 3:
        fail("Points must have 3 components")
    check_arrays(f, {"Points": f.points}, npts, "Points")
    names = check_arrays(f, f.point_data, npts, "PointData")
    names += check_arrays(f, f.cell_data, ncells, "CellData")
    if args.points is not None and npts != args.points:
        fail(f"NumberOfPoints={npts}, expected {args.points}")
    if args.cells is not None and ncells != args.cells:
        fail(f"{ncells} cells, expected {args.cells}")
    for name in (args.arrays.split(",") if args.arrays else []):
        if name not in names:
            fail(f"missing data array {name}")
    if args.format and (npts or ncells) and encoding(f) != args.format:
        fail(f"arrays stored as {encoding(f)}, expected {args.format}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("file")
    ap.add_argument("--points", type=int)
    ap.add_argument("--cells", type=int)
    ap.add_argument("--arrays")
    ap.add_argument("--format", choices=["ascii", "binary", "zlib"])
    ap.add_argument("--datasets", type=int)
    args = ap.parse_args()
    with open(args.file, "rb") as f:
        head = f.read(21)
    if head != b'<?xml version="1.0"?>':
        fail("file does not start with <?xml version=\"1.0\"?>")
    try:
        f = vtkxml.read(args.file)
    except (ET.ParseError, vtkxml.VtkFileError, ValueError, OSError) as e:
        fail(f"unreadable: {e}")
    if f.type == "Collection":
        root = ET.parse(args.file).getroot()
        sets = root.findall("Collection/DataSet")
        if args.datasets is not None and len(sets) != args.datasets:
            fail(f"{len(sets)} DataSet entries, expected {args.datasets}")
        return
    if f.type != "PolyData":
        fail(f"VTKFile type {f.type}, expected PolyData")
    if not f.piece:
        fail("no piece")
    check_piece(f, args)


if __name__ == "__main__":
    main()
