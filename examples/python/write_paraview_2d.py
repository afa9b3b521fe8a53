#!/usr/bin/env python3
"""A small 2D contact code of one's own, writing ParaView files for `signorini verify`.

It solves the 2D/3D note's 2D bar (Dabaghi, Petrov, Pousin, Renard, "Numerical study of
convergence of the mass redistribution method for elastodynamic contact problems", section 3,
as scenes/bar2d.json sets it up): the box [0, 0.1] x [0, 1] with density 1 and the Lame
coefficients lambda = 0.25, mu = 0.5 (plane strain), its top face x2 = 1 held (u = 0), every
other node starting at rest in its place with the velocity (0, -0.5), the obstacle 0.2 below
the bottom face x2 = 0:

    rho u_tt - div sigma(u) = 0,   sigma = lambda tr(eps) I + 2 mu eps,
    u_2(x1, 0, t) + 0.2 >= 0,  lambda_i <= 0,  (u_2 + 0.2) lambda_i = 0 at every bottom node,
    0 <= t <= T = 2,

with Q1 elements (NX along the bar, NX/10 across: squares of side h = 1/NX), the consistent
("standard") mass M, the stiffness S and Crank-Nicolson (Newmark, beta = 1/4, gamma = 1/2)
at the note's ratio h/dt = 2:

    M A^{n+1} + S U^{n+1} = -B^T lambda^{n+1},
    U^{n+1} = U^n + dt V^n + dt^2/4 (A^n + A^{n+1}),   V^{n+1} = V^n + dt/2 (A^n + A^{n+1}).

With K = 4 M / dt^2 + S (a band matrix, factorised once) the free solution U* and the columns
K^{-1} B^T give U^{n+1} = U* - K^{-1} B^T lambda; the contact condition is the small linear
complementarity problem of the Delassus matrix W = B K^{-1} B^T, solved by projected
Gauss-Seidel to round-off.

Each level NX is written to OUT_DIR/nxNX/: one ASCII .vtu file per step (point data
`displacement`, `velocity`, `contact_multiplier`) and the collection fields.pvd.

Usage: python3 write_paraview_2d.py OUT_DIR [NX ...]   (levels 10 20 40 by default; NX a
multiple of 10). Plain Python 3, no third-party module.
"""

import os
import sys

WIDTH, LENGTH = 0.1, 1.0
DENSITY, LAME_LAMBDA, LAME_MU = 1.0, 0.25, 0.5
GAP = 0.2
INITIAL_VELOCITY = -0.5
HORIZON = 2.0
RATIO = 2.0  # h / dt, the note's ratio

GAUSS = (-3.0 ** -0.5, 3.0 ** -0.5)
CORNERS = ((-1, -1), (1, -1), (1, 1), (-1, 1))  # counter-clockwise, as VTK_QUAD


def element_matrices(h):
    """The Q1 element's mass and stiffness (8 x 8, dofs corner-major), 2 x 2 Gauss points."""
    d = [
        [LAME_LAMBDA + 2 * LAME_MU, LAME_LAMBDA, 0.0],
        [LAME_LAMBDA, LAME_LAMBDA + 2 * LAME_MU, 0.0],
        [0.0, 0.0, LAME_MU],
    ]
    mass = [[0.0] * 8 for _ in range(8)]
    stiffness = [[0.0] * 8 for _ in range(8)]
    jacobian = h * h / 4.0
    for xi in GAUSS:
        for eta in GAUSS:
            n = [(1 + xi * a) * (1 + eta * b) / 4 for a, b in CORNERS]
            dx = [a * (1 + eta * b) / 4 * 2 / h for a, b in CORNERS]
            dy = [b * (1 + xi * a) / 4 * 2 / h for a, b in CORNERS]
            strain = [[0.0] * 8 for _ in range(3)]  # rows: eps_11, eps_22, 2 eps_12
            for k in range(4):
                strain[0][2 * k] = dx[k]
                strain[1][2 * k + 1] = dy[k]
                strain[2][2 * k] = dy[k]
                strain[2][2 * k + 1] = dx[k]
            for i in range(8):
                di = [sum(d[r][s] * strain[s][i] for s in range(3)) for r in range(3)]
                for j in range(8):
                    stiffness[i][j] += jacobian * sum(di[r] * strain[r][j] for r in range(3))
                    if i % 2 == j % 2:
                        mass[i][j] += jacobian * DENSITY * n[i // 2] * n[j // 2]
    return mass, stiffness


class Band:
    """A symmetric band matrix (half-bandwidth `width`), its Cholesky factor and solves."""

    def __init__(self, size, width):
        self.size, self.width = size, width
        self.rows = [[0.0] * (width + 1) for _ in range(size)]  # rows[i][k] = A[i][i - k]

    def add(self, i, j, value):
        if i >= j:
            self.rows[i][i - j] += value

    def product(self, x):
        y = [0.0] * self.size
        for i, row in enumerate(self.rows):
            y[i] += row[0] * x[i]
            for k in range(1, min(self.width, i) + 1):
                y[i] += row[k] * x[i - k]
                y[i - k] += row[k] * x[i]
        return y

    def factorise(self):
        """Overwrites the matrix with its Cholesky factor L (A = L L^T)."""
        r = self.rows
        for i in range(self.size):
            for k in range(min(self.width, i), 0, -1):
                j = i - k
                s = r[i][k]
                for m in range(k + 1, min(self.width, i) + 1):
                    if m - k <= self.width:
                        s -= r[i][m] * r[j][m - k]
                r[i][k] = s / r[j][0]
            r[i][0] = (r[i][0] - sum(v * v for v in r[i][1 : min(self.width, i) + 1])) ** 0.5
        return self

    def solve(self, b):
        r, n, w = self.rows, self.size, self.width
        y = list(b)
        for i in range(n):
            for k in range(1, min(w, i) + 1):
                y[i] -= r[i][k] * y[i - k]
            y[i] /= r[i][0]
        for i in range(n - 1, -1, -1):
            y[i] /= r[i][0]
            for k in range(1, min(w, i) + 1):
                y[i - k] -= r[i][k] * y[i]
        return y


def solve(nx, write_step):
    """Crank-Nicolson on the level nx, each step handed to write_step(n, t, U, V, lambda)."""
    n1, n2 = nx // 10, nx
    h = LENGTH / n2
    dt = h / RATIO
    steps = round(HORIZON / dt)
    free_nodes = (n1 + 1) * n2  # the top row (i2 = n2) is held and carries no unknown
    size = 2 * free_nodes
    width = 2 * (n1 + 2) + 1
    mass, stiffness = Band(size, width), Band(size, width)
    element_mass, element_stiffness = element_matrices(h)
    for e2 in range(n2):
        for e1 in range(n1):
            nodes = [(e1 + a) + (n1 + 1) * (e2 + b) for a, b in ((0, 0), (1, 0), (1, 1), (0, 1))]
            dofs = [2 * node + c for node in nodes for c in (0, 1)]
            for i, gi in enumerate(dofs):
                for j, gj in enumerate(dofs):
                    if gi < size and gj < size:
                        mass.add(gi, gj, element_mass[i][j])
                        stiffness.add(gi, gj, element_stiffness[i][j])
    c = 4.0 / (dt * dt)
    step = Band(size, width)
    step.rows = [[c * m + s for m, s in zip(mr, sr)] for mr, sr in zip(mass.rows, stiffness.rows)]
    step.factorise()
    contact = [2 * i1 + 1 for i1 in range(n1 + 1)]  # u_2 of the bottom nodes
    columns = []
    for dof in contact:
        e = [0.0] * size
        e[dof] = 1.0
        columns.append(step.solve(e))
    delassus = [[col[dof] for dof in contact] for col in columns]

    u = [0.0] * size
    v = [INITIAL_VELOCITY if k % 2 else 0.0 for k in range(size)]
    a = [0.0] * size  # M A^0 = -S U^0 = 0, no contact at the start
    mu = [0.0] * len(contact)  # mu = -lambda >= 0
    write_step(0, 0.0, u, v, mu)
    for n in range(1, steps + 1):
        predictor = [ui + dt * vi + 0.25 * dt * dt * ai for ui, vi, ai in zip(u, v, a)]
        free = step.solve(mass.product([c * p for p in predictor]))
        gaps = [free[dof] + GAP for dof in contact]
        mu = projected_gauss_seidel(delassus, gaps, mu)
        u_new = list(free)
        for m, col in zip(mu, columns):
            if m:
                u_new = [ui + m * ci for ui, ci in zip(u_new, col)]
        a_new = [c * (un - p) for un, p in zip(u_new, predictor)]
        v = [vi + 0.5 * dt * (ai + an) for vi, ai, an in zip(v, a, a_new)]
        u, a = u_new, a_new
        write_step(n, n * dt, u, v, mu)


def projected_gauss_seidel(w, gaps, start):
    """mu >= 0 with g = gaps + W mu >= 0 and mu . g = 0, from `start`, to round-off."""
    mu = list(start)
    for _ in range(10000):
        change = 0.0
        for i in range(len(mu)):
            g = gaps[i] + sum(w[i][j] * mu[j] for j in range(len(mu)))
            new = max(0.0, mu[i] - g / w[i][i])
            change = max(change, abs(new - mu[i]))
            mu[i] = new
        if change <= 1e-15 * (1.0 + max(mu)):
            return mu
    sys.exit("projected Gauss-Seidel did not converge")


def vtu(nx, u, v, mu):
    """The ASCII .vtu document of one step on the level nx (points x1 fastest, then x2)."""
    n1, n2 = nx // 10, nx
    h = LENGTH / n2
    points = [(i1 * h, i2 * h) for i2 in range(n2 + 1) for i1 in range(n1 + 1)]
    cells = [
        [(e1 + a) + (n1 + 1) * (e2 + b) for a, b in ((0, 0), (1, 0), (1, 1), (0, 1))]
        for e2 in range(n2)
        for e1 in range(n1)
    ]
    held = 2 * len(points) - len(u)
    u, v = u + [0.0] * held, v + [0.0] * held
    multiplier = [-m for m in mu] + [0.0] * (len(points) - len(mu))

    def vectors(values):
        return " ".join("%r %r 0" % (values[2 * k], values[2 * k + 1]) for k in range(len(points)))

    return "\n".join(
        [
            '<?xml version="1.0"?>',
            '<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">',
            "<UnstructuredGrid>",
            '<Piece NumberOfPoints="%d" NumberOfCells="%d">' % (len(points), len(cells)),
            "<Points>",
            '<DataArray type="Float64" NumberOfComponents="3" format="ascii">',
            " ".join("%r %r 0" % p for p in points),
            "</DataArray>",
            "</Points>",
            "<Cells>",
            '<DataArray type="Int64" Name="connectivity" format="ascii">',
            " ".join(str(k) for cell in cells for k in cell),
            "</DataArray>",
            '<DataArray type="Int64" Name="offsets" format="ascii">',
            " ".join(str(4 * (k + 1)) for k in range(len(cells))),
            "</DataArray>",
            '<DataArray type="UInt8" Name="types" format="ascii">',
            " ".join("9" for _ in cells),
            "</DataArray>",
            "</Cells>",
            "<PointData>",
            '<DataArray type="Float64" Name="displacement" NumberOfComponents="3" format="ascii">',
            vectors(u),
            "</DataArray>",
            '<DataArray type="Float64" Name="velocity" NumberOfComponents="3" format="ascii">',
            vectors(v),
            "</DataArray>",
            '<DataArray type="Float64" Name="contact_multiplier" format="ascii">',
            " ".join(repr(m) for m in multiplier),
            "</DataArray>",
            "</PointData>",
            "</Piece>",
            "</UnstructuredGrid>",
            "</VTKFile>",
            "",
        ]
    )


def write_level(out, nx):
    """The level nx's .vtu files and their collection OUT/nxNX/fields.pvd."""
    directory = os.path.join(out, "nx%d" % nx)
    os.makedirs(directory, exist_ok=True)
    entries = []

    def write_step(n, t, u, v, mu):
        name = "step-%05d.vtu" % n
        with open(os.path.join(directory, name), "w") as f:
            f.write(vtu(nx, u, v, mu))
        entries.append('<DataSet timestep="%r" part="0" file="%s"/>' % (t, name))

    solve(nx, write_step)
    path = os.path.join(directory, "fields.pvd")
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n')
        f.write("\n".join(entries))
        f.write("\n</Collection>\n</VTKFile>\n")
    return path


def main(argv):
    if len(argv) < 2:
        sys.exit("usage: write_paraview_2d.py OUT_DIR [NX ...]")
    levels = [int(a) for a in argv[2:]] or [10, 20, 40]
    if any(nx % 10 for nx in levels):
        sys.exit("every NX must be a multiple of 10 (NX/10 elements across the bar)")
    for nx in levels:
        print(write_level(argv[1], nx))


if __name__ == "__main__":
    main(sys.argv)
