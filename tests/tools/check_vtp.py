#!/usr/bin/env python3
"""Structural check of a VTK XML PolyData (.vtp) or collection (.pvd) file written by Sable.

Parses the file with xml.etree and checks that every DataArray has as many values as its
section declares (PointData: NumberOfPoints tuples, CellData: one tuple per cell, Points: 3 per
point), that the cell connectivity/offsets are consistent and index existing points, and
optionally that the counts and array names are the expected ones. Exit status 0 when the file
is well-formed, 1 (with the reason on stderr) otherwise.

usage: check_vtp.py FILE.vtp [--points N] [--cells N] [--arrays name,name,...]
       check_vtp.py FILE.pvd --datasets N
"""
import argparse
import math
import sys
import xml.etree.ElementTree as ET

CELL_TAGS = (("Verts", "NumberOfVerts"), ("Lines", "NumberOfLines"),
             ("Strips", "NumberOfStrips"), ("Polys", "NumberOfPolys"))
INT_TYPES = {"Int8", "Int16", "Int32", "Int64", "UInt8", "UInt16", "UInt32", "UInt64"}


def fail(msg):
    print(f"check_vtp: {msg}", file=sys.stderr)
    sys.exit(1)


def values(arr):
    words = (arr.text or "").split()
    kind = arr.get("type")
    try:
        if kind in INT_TYPES:
            return [int(w) for w in words]
        if kind in ("Float32", "Float64"):
            vals = [float(w) for w in words]
            if not all(math.isfinite(v) for v in vals):
                fail(f"array {arr.get('Name')} has non-finite values")
            return vals
    except ValueError as e:
        fail(f"array {arr.get('Name')}: {e}")
    fail(f"array {arr.get('Name')} has unknown type {kind}")


def check_arrays(section, tuples, where):
    names = []
    for arr in section.findall("DataArray"):
        comps = int(arr.get("NumberOfComponents", "1"))
        n = len(values(arr))
        if n != tuples * comps:
            fail(f"{where} array {arr.get('Name')}: {n} values, expected {tuples} x {comps}")
        names.append(arr.get("Name"))
    return names


def check_piece(piece, args):
    npts = int(piece.get("NumberOfPoints"))
    ncells = 0
    for tag, attr in CELL_TAGS:
        declared = int(piece.get(attr, "0"))
        ncells += declared
        sec = piece.find(tag)
        if sec is None:
            if declared:
                fail(f"{attr}={declared} but no <{tag}> section")
            continue
        arrays = {a.get("Name"): values(a) for a in sec.findall("DataArray")}
        conn, offs = arrays.get("connectivity"), arrays.get("offsets")
        if conn is None or offs is None:
            fail(f"<{tag}> lacks connectivity or offsets")
        if len(offs) != declared:
            fail(f"<{tag}>: {len(offs)} offsets for {attr}={declared}")
        if offs and (offs[-1] != len(conn) or offs != sorted(offs)):
            fail(f"<{tag}>: offsets do not partition the connectivity")
        if any(c < 0 or c >= npts for c in conn):
            fail(f"<{tag}>: connectivity indexes a missing point")
    pts = piece.find("Points")
    if pts is None:
        fail("no <Points> section")
    check_arrays(pts, npts, "Points")
    if pts.find("DataArray").get("NumberOfComponents") != "3":
        fail("Points must have 3 components")
    names = []
    if piece.find("PointData") is not None:
        names += check_arrays(piece.find("PointData"), npts, "PointData")
    if piece.find("CellData") is not None:
        names += check_arrays(piece.find("CellData"), ncells, "CellData")
    if args.points is not None and npts != args.points:
        fail(f"NumberOfPoints={npts}, expected {args.points}")
    if args.cells is not None and ncells != args.cells:
        fail(f"{ncells} cells, expected {args.cells}")
    for name in (args.arrays.split(",") if args.arrays else []):
        if name not in names:
            fail(f"missing data array {name}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("file")
    ap.add_argument("--points", type=int)
    ap.add_argument("--cells", type=int)
    ap.add_argument("--arrays")
    ap.add_argument("--datasets", type=int)
    args = ap.parse_args()
    with open(args.file, "rb") as f:
        head = f.read(21)
    if head != b'<?xml version="1.0"?>':
        fail("file does not start with <?xml version=\"1.0\"?>")
    try:
        root = ET.parse(args.file).getroot()
    except ET.ParseError as e:
        fail(f"not well-formed XML: {e}")
    if root.tag != "VTKFile":
        fail(f"root element is {root.tag}, expected VTKFile")
    if root.get("type") == "Collection":
        sets = root.findall("Collection/DataSet")
        if args.datasets is not None and len(sets) != args.datasets:
            fail(f"{len(sets)} DataSet entries, expected {args.datasets}")
        return
    if root.get("type") != "PolyData":
        fail(f"VTKFile type {root.get('type')}, expected PolyData")
    pieces = root.findall("PolyData/Piece")
    if len(pieces) != 1:
        fail(f"{len(pieces)} pieces, expected 1")
    check_piece(pieces[0], args)


if __name__ == "__main__":
    main()
