#!/usr/bin/python3
"""Simplex meshes of the box bars with a field known in closed form, as VTK unstructured grids.

Run with plain python3 (no package needed):

    python3 scripts/mesh_fixtures.py --out tests/data/mesh

It writes two ASCII ``.vtu`` files, the fixtures of ``tests/cli/verify_mesh.rs`` (issue 57):

- ``bar2d-triangles.vtu``: the 2D bar's box [0, 0.1] × [0, 1] on a 2 × 5 grid, each square cut
  along its diagonal 0–2 into two ``VTK_TRIANGLE`` (5);
- ``bar3d-tetrahedra.vtu``: the 3D bar's box [0, 0.1]² × [0, 1] on a 2 × 2 × 5 grid, each cube
  cut into the six ``VTK_TETRA`` (10) around its diagonal 0–6 (Kuhn's triangulation, conforming).

**The mesh is not the scene's**: every grid coordinate strictly inside its axis's range is moved
by 0.15 of the element's size (x_c += 0.15 h_c sin(7 i_1 + 3 i_2 + 5 i_3 + c), ``i`` the node's
grid index), so nodes on a face stay on it and the cells are nested in no structured mesh; the
points are listed in a shuffled order (a fixed permutation: i ↦ 7 i mod N, N coprime to 7) and
the cells in reverse order.

**The field** ``displacement`` (three components, the third 0 in 2D) is the nodal interpolant of
the multilinear

    f(x) = (m, 2 m + x_1, m − x_1 x_2),   m = x_1 x_2 (x_1 x_2 x_3 in 3D; the third component 0
    in 2D):

on these simplices a P1 function. The structured Q1 reference reproduces f exactly and P1 does
not, so the field's distance to the reference is its distance to f, computed exactly on the
simplices (``simplex_errors`` in the test). Every number is written with Python's ``repr`` (it reads
back to the same double).
"""

import argparse
import math
import os

LENGTHS = {2: [0.1, 1.0], 3: [0.1, 0.1, 1.0]}
COUNTS = {2: [2, 5], 3: [2, 2, 5]}
QUAD_CORNERS = [(0, 0), (1, 0), (1, 1), (0, 1)]
HEX_CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
KUHN_RING = [(1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1)]


def grid(d):
    """The grid's nodes (index tuples, x_1 fastest) and their moved coordinates."""
    counts, lengths = COUNTS[d], LENGTHS[d]
    indices = []
    if d == 2:
        indices = [(i, j) for j in range(counts[1] + 1) for i in range(counts[0] + 1)]
    else:
        indices = [
            (i, j, k)
            for k in range(counts[2] + 1)
            for j in range(counts[1] + 1)
            for i in range(counts[0] + 1)
        ]
    points = []
    for index in indices:
        x = []
        for c in range(d):
            h = lengths[c] / counts[c]
            value = lengths[c] if index[c] == counts[c] else index[c] * h
            if 0 < index[c] < counts[c]:
                phase = 7 * index[0] + 3 * index[1] + (5 * index[2] if d == 3 else 0) + c
                value += 0.15 * h * math.sin(phase)
            x.append(value)
        points.append(x)
    return indices, points


def cells(d, indices):
    """The simplices of the grid, as node numbers in the grid's order."""
    counts = COUNTS[d]
    number = {index: n for n, index in enumerate(indices)}
    out = []
    if d == 2:
        for j in range(counts[1]):
            for i in range(counts[0]):
                q = [number[(i + a, j + b)] for a, b in QUAD_CORNERS]
                out += [(5, [q[0], q[1], q[2]]), (5, [q[0], q[2], q[3]])]
    else:
        for k in range(counts[2]):
            for j in range(counts[1]):
                for i in range(counts[0]):
                    h = [number[(i + a, j + b, k + c)] for a, b, c in HEX_CORNERS]
                    out += [(10, [h[0], h[a], h[b], h[6]]) for a, b in KUHN_RING]
    return out


def field(d, x):
    """f(x): three components, the third 0 in 2D."""
    m = math.prod(x[:d])
    return [m, 2.0 * m + x[0], m - x[0] * x[1] if d == 3 else 0.0]


def write(path, d):
    """Writes the fixture of dimension ``d`` to ``path``."""
    indices, points = grid(d)
    n = len(points)
    assert math.gcd(n, 7) == 1
    # File point p is grid node order[p]; grid node g is file point position[g].
    order = [(7 * p) % n for p in range(n)]
    position = {g: p for p, g in enumerate(order)}
    listed = [(vtk, [position[g] for g in nodes]) for vtk, nodes in reversed(cells(d, indices))]
    coordinates = [points[g] + [0.0] * (3 - d) for g in order]
    values = [field(d, points[g]) for g in order]
    offsets, end = [], 0
    for _, nodes in listed:
        end += len(nodes)
        offsets.append(end)

    def numbers(rows):
        return " ".join(repr(float(v)) for row in rows for v in row)

    text = (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">\n'
        "<UnstructuredGrid>\n"
        f'<Piece NumberOfPoints="{n}" NumberOfCells="{len(listed)}">\n'
        "<PointData>\n"
        '<DataArray type="Float64" Name="displacement" NumberOfComponents="3" format="ascii">'
        f"{numbers(values)}</DataArray>\n"
        "</PointData>\n"
        "<Points>\n"
        '<DataArray type="Float64" NumberOfComponents="3" format="ascii">'
        f"{numbers(coordinates)}</DataArray>\n"
        "</Points>\n"
        "<Cells>\n"
        '<DataArray type="Int64" Name="connectivity" format="ascii">'
        f"{' '.join(str(p) for _, nodes in listed for p in nodes)}</DataArray>\n"
        '<DataArray type="Int64" Name="offsets" format="ascii">'
        f"{' '.join(map(str, offsets))}</DataArray>\n"
        '<DataArray type="UInt8" Name="types" format="ascii">'
        f"{' '.join(str(vtk) for vtk, _ in listed)}</DataArray>\n"
        "</Cells>\n"
        "</Piece>\n"
        "</UnstructuredGrid>\n"
        "</VTKFile>\n"
    )
    with open(path, "w", encoding="utf-8") as out:
        out.write(text)


def main():
    """Writes both fixtures into ``--out``."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default="tests/data/mesh")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    write(os.path.join(args.out, "bar2d-triangles.vtu"), 2)
    write(os.path.join(args.out, "bar3d-tetrahedra.vtu"), 3)


if __name__ == "__main__":
    main()
