"""Read the VTK XML files Sable writes (.vtp PolyData, .vti ImageData) into numpy arrays.

Sable's arrays are raw binary by default, zlib-compressed or ASCII on request
(src/sable/io/vtk_xml.hpp, [output] vtk_format, `sable analyze --vtk-format`). This module
reads all three with the standard library and numpy only, so scripts need no VTK install:

    import vtkxml
    f = vtkxml.read("out/vtk/grains_0000001000.vtp")
    f.points            # (n, 3) float64
    f.point_data["radius"], f.cell_data, f.cells["Verts"] = (connectivity, offsets)
    f.piece["NumberOfPoints"], f.image (ImageData: WholeExtent, Origin, Spacing)

The appended section holds raw bytes, which no XML parser accepts: the XML before it is parsed
on its own, and each array is read at its offset after the section's '_' marker: a UInt64 (or
UInt32, header_type) byte count then the bytes; compressed: [blocks, block size, last partial
block size (0: full), compressed size of each block] then the zlib blocks.
"""
import xml.etree.ElementTree as ET
import zlib

import numpy as np

DTYPES = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "Int16": "<i2",
          "Int8": "i1", "UInt64": "<u8", "UInt32": "<u4", "UInt16": "<u2", "UInt8": "u1"}
CELL_TAGS = ("Verts", "Lines", "Strips", "Polys")


class VtkFileError(ValueError):
    """A file this module cannot read, with the path and the reason."""


class VtkFile:
    def __init__(self):
        self.type = None
        self.attrs = {}      # the <VTKFile> element's attributes
        self.piece = {}      # the <Piece> element's attributes
        self.image = {}      # ImageData's attributes (WholeExtent, Origin, Spacing)
        self.points = None   # (n, 3)
        self.point_data = {}
        self.cell_data = {}
        self.cells = {}      # tag -> (connectivity, offsets)
        self.components = {}  # array name -> NumberOfComponents
        self.formats = set()  # the DataArray formats met: ascii, appended


def split_appended(data):
    """(XML text without the appended bytes, the bytes after '_', or None)."""
    start = data.find(b"<AppendedData")
    if start < 0:
        return data, None
    marker = data.index(b"_", data.index(b">", start))
    return data[:start] + b"</VTKFile>\n", data[marker + 1:]


def decode_appended(blob, offset, dtype, root, path):
    header = np.dtype("<u8" if root.get("header_type", "UInt32") == "UInt64" else "<u4")
    size = header.itemsize

    def words(at, count):
        if at + count * size > len(blob):
            raise VtkFileError(f"{path}: appended data ends inside an array header")
        return np.frombuffer(blob, dtype=header, count=count, offset=at).astype(np.int64)

    if root.get("compressor") is None:
        (nbytes,) = words(offset, 1)
        raw = blob[offset + size:offset + size + nbytes]
        if len(raw) != nbytes:
            raise VtkFileError(f"{path}: an array declares {nbytes} bytes, {len(raw)} present")
    else:
        if root.get("compressor") != "vtkZLibDataCompressor":
            raise VtkFileError(f"{path}: unknown compressor {root.get('compressor')}")
        blocks, block, last = words(offset, 3)
        sizes = words(offset + 3 * size, blocks)
        at, parts = offset + (3 + blocks) * size, []
        for b, c in enumerate(sizes):
            part = zlib.decompress(blob[at:at + c])
            want = last if (b == blocks - 1 and last) else block
            if len(part) != want:
                raise VtkFileError(f"{path}: block {b} inflates to {len(part)} bytes, not {want}")
            parts.append(part)
            at += c
        raw = b"".join(parts)
    if len(raw) % np.dtype(dtype).itemsize:
        raise VtkFileError(f"{path}: {len(raw)} bytes is not a whole number of {dtype}")
    return np.frombuffer(raw, dtype=dtype)


def array(da, blob, root, path):
    kind = da.get("type")
    if kind not in DTYPES:
        raise VtkFileError(f"{path}: array {da.get('Name')} has unknown type {kind}")
    fmt = da.get("format")
    if fmt == "ascii":
        values = np.array((da.text or "").split(), dtype=DTYPES[kind])
    elif fmt == "appended":
        if blob is None:
            raise VtkFileError(f"{path}: array {da.get('Name')} is appended but no AppendedData")
        values = decode_appended(blob, int(da.get("offset")), DTYPES[kind], root, path)
    else:
        raise VtkFileError(f"{path}: array {da.get('Name')} has format {fmt}")
    comps = int(da.get("NumberOfComponents", "1"))
    return fmt, (values.reshape(-1, comps) if comps > 1 and values.size % comps == 0 else values)


def read(path):
    """The file at `path` as a VtkFile; raises VtkFileError (or ET.ParseError) if unreadable."""
    with open(path, "rb") as f:
        data = f.read()
    text, blob = split_appended(data)
    root = ET.fromstring(text)
    if root.tag != "VTKFile":
        raise VtkFileError(f"{path}: root element is {root.tag}, expected VTKFile")
    out = VtkFile()
    out.type, out.attrs = root.get("type"), dict(root.attrib)
    dataset = root.find(out.type) if out.type else None
    if dataset is None:
        return out
    out.image = dict(dataset.attrib)
    piece = dataset.find("Piece")
    if piece is None:
        return out
    out.piece = dict(piece.attrib)

    def arrays(node):
        found = {}
        for da in ([] if node is None else node.findall("DataArray")):
            fmt, values = array(da, blob, root, path)
            out.formats.add(fmt)
            out.components[da.get("Name")] = int(da.get("NumberOfComponents", "1"))
            found[da.get("Name")] = values
        return found

    out.point_data = arrays(piece.find("PointData"))
    out.cell_data = arrays(piece.find("CellData"))
    pts = arrays(piece.find("Points"))
    if pts:
        out.points = next(iter(pts.values()))
    for tag in CELL_TAGS:
        sec = piece.find(tag)
        if sec is not None:
            a = arrays(sec)
            out.cells[tag] = (a.get("connectivity"), a.get("offsets"))
    return out
