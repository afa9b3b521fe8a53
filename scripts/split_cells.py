"""Re-mesh a box run's ParaView collection into simplices on the same nodes.

Run: python3 scripts/split_cells.py RUN/fields.pvd OUT_DIR

Reads the collection `signorini run SCENE --out RUN --fields-every-step` writes (binary
`.vtu` snapshots, UInt64 headers) and writes OUT_DIR/fields.pvd, each snapshot's Q1 cells
replaced by simplices on the same points with the same point data: every quadrilateral
(VTK 9) cut along its diagonal 0-2 into two triangles (VTK 5), every hexahedron (VTK 12)
into six Kuhn tetrahedra around its diagonal 0-6 (VTK 10). The nodal values are kept, so
the field the file then defines is the P1 interpolant of the harness's Q1 field on the same
nodes (another finite element function): what `signorini verify` measures on its own mesh
(docs/src/external-runs.md, "A code's own mesh"). Other files of the collection (the
obstacle) are copied unchanged.
"""

import base64
import os
import re
import shutil
import struct
import sys


def decode(text, fmt):
    """The values of a binary VTK DataArray (base64, a UInt64 byte count first)."""
    raw = base64.b64decode(text)
    (size,) = struct.unpack("<Q", raw[:8])
    width = struct.calcsize("<" + fmt)
    return list(struct.unpack("<%d%s" % (size // width, fmt), raw[8 : 8 + size]))


def encode(values, fmt):
    """`values` as a binary VTK DataArray's text."""
    body = struct.pack("<%d%s" % (len(values), fmt), *values)
    return base64.b64encode(struct.pack("<Q", len(body)) + body).decode()


def split(kind, points):
    """The simplices (VTK type, points) one cell of VTK type `kind` is cut into."""
    if kind == 9:
        q = points
        return [(5, [q[0], q[1], q[2]]), (5, [q[0], q[2], q[3]])]
    if kind == 12:
        h = points
        pairs = [(1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1)]
        return [(10, [h[0], h[a], h[b], h[6]]) for a, b in pairs]
    raise SystemExit("a cell of VTK type %d: only quadrilaterals and hexahedra are split" % kind)


ARRAY = r'(<DataArray type="{t}" Name="{n}" format="binary"[^>]*>)([^<]*)(</DataArray>)'


def split_vtu(text):
    """The `.vtu` text `text` with its cells split."""
    found = {}
    for name, vtype in (("connectivity", "UInt64"), ("offsets", "UInt64"), ("types", "UInt8")):
        match = re.search(ARRAY.format(t=vtype, n=name), text)
        if match is None:
            raise SystemExit("no binary %s %s array" % (vtype, name))
        found[name] = match
    fmt = {"connectivity": "Q", "offsets": "Q", "types": "B"}
    connectivity = decode(found["connectivity"].group(2), "Q")
    offsets = decode(found["offsets"].group(2), "Q")
    types = decode(found["types"].group(2), "B")
    new = {"connectivity": [], "offsets": [], "types": []}
    start = 0
    for kind, end in zip(types, offsets):
        for vtk, points in split(kind, connectivity[start:end]):
            new["connectivity"].extend(points)
            new["offsets"].append(len(new["connectivity"]))
            new["types"].append(vtk)
        start = end
    for name in ("connectivity", "offsets", "types"):
        match = found[name]
        opening = re.sub(r' RangeMin="[^"]*" RangeMax="[^"]*"', "", match.group(1))
        replaced = opening + encode(new[name], fmt[name]) + match.group(3)
        text = text.replace(match.group(0), replaced, 1)
    cells = len(new["types"])
    return re.sub(r'NumberOfCells="\d+"', 'NumberOfCells="%d"' % cells, text, count=1)


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    pvd, out = sys.argv[1], sys.argv[2]
    source = os.path.dirname(os.path.abspath(pvd))
    os.makedirs(out, exist_ok=True)
    collection = open(pvd).read()
    for dataset in re.finditer(r'<DataSet[^>]*part="(\d+)"[^>]*file="([^"]+)"', collection):
        part, name = dataset.group(1), dataset.group(2)
        target = os.path.join(out, name)
        if part == "0":
            with open(os.path.join(source, name)) as f:
                text = f.read()
            with open(target, "w") as f:
                f.write(split_vtu(text))
        else:
            shutil.copyfile(os.path.join(source, name), target)
    with open(os.path.join(out, os.path.basename(pvd)), "w") as f:
        f.write(collection)


if __name__ == "__main__":
    main()
