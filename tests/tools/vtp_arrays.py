#!/usr/bin/env python3
"""Print a VTK XML PolyData file's arrays as text that keeps every bit, for C++ tests.

Reads FILE.vtp with scripts/vtkxml.py (ASCII, raw appended or zlib-compressed arrays) and
writes one line per array to OUT: its key, then its values flattened. Keys: `piece/NAME` (the
<Piece> element's counts), `Points`, `point/NAME`, `cell/NAME`, `TAG/connectivity` and
`TAG/offsets` (TAG: Verts, Lines, Strips, Polys). Reals are written by repr(), which reads back
(strtod) as the same double; integers as integers. Exit status 0, or 1 with the reason on
stderr.

usage: vtp_arrays.py FILE.vtp OUT.txt
"""
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "scripts"))
import vtkxml  # noqa: E402


def line(key, values):
    flat = np.asarray(values).ravel()
    if flat.dtype.kind == "f":
        text = " ".join(repr(float(v)) for v in flat)
    else:
        text = " ".join(str(int(v)) for v in flat)
    return f"{key} {text}".rstrip() + "\n"


def main():
    if len(sys.argv) != 3:
        print("usage: vtp_arrays.py FILE.vtp OUT.txt", file=sys.stderr)
        return 1
    try:
        f = vtkxml.read(sys.argv[1])
    except (ET.ParseError, vtkxml.VtkFileError, ValueError, OSError) as e:
        print(f"vtp_arrays: unreadable: {e}", file=sys.stderr)
        return 1
    out = []
    for name, value in f.piece.items():
        out.append(line(f"piece/{name}", [int(value)]))
    if f.points is not None:
        out.append(line("Points", f.points))
    for prefix, arrays in (("point", f.point_data), ("cell", f.cell_data)):
        for name, values in arrays.items():
            out.append(line(f"{prefix}/{name}", values))
    for tag, (connectivity, offsets) in f.cells.items():
        out.append(line(f"{tag}/connectivity", connectivity))
        out.append(line(f"{tag}/offsets", offsets))
    with open(sys.argv[2], "w") as o:
        o.writelines(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
