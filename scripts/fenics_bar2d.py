#!/usr/bin/python3
"""Legacy FEniCS's matrices of the 2D bar (``scenes/bar2d.json``), stepped with an exact nodal
contact solve and written every step with legacy FEniCS's ``XDMFFile``, as external runs.

Run with Debian's Python (python3-dolfin 2019.2, numpy, scipy):

    apt-get install -y python3-dolfin
    /usr/bin/python3 scripts/fenics_bar2d.py --level 10 20 --scheme crank-nicolson \
        --mass standard --out target/fenics-runs

For each LEVEL it writes ``fenics-bar2d-<scheme>-<mass>-level<LEVEL>.xdmf`` and its heavy data
``….h5`` in OUT, meant for ``signorini verify scenes/bar2d.json RUN.xdmf --code fenics
--code-version 2019.2 --scheme <scheme> --mass <mass> --velocity velocity --multiplier
contact_multiplier``, and prints one line per run (the steps, the energy at t = 0 and t = T,
the largest total contact force and the largest complementarity product).

**The discrete problem and the schemes** are those of ``dolfinx_bar2d.py`` (its docstring):
the same Q1 space on the same quadrilateral mesh (here ``RectangleMesh.create`` with
``CellType.Type.quadrilateral``), the forms integrated with ``quadrature_degree`` 2 and assembled
by ``dolfin.assemble``, the same clamped face, obstacle, time grid and initial data, stepped by
``bar2d_contact.stepped``.

**What legacy FEniCS writes** (``XDMFFile`` with ``functions_share_mesh`` and without
``rewrite_function_mesh``, ``write(f, t)`` for the three functions at every t_n): one temporal
collection ``TimeSeries``; its first grid holds the mesh (``/Mesh/0/mesh/geometry``, XY) and
every later grid includes it (``xi:include``); each grid has ``<Time Value="…"/>`` printed with
16 significant digits and the functions as ``Attribute``s with ``Center="Node"`` (vectors padded
to three components, ``/VisualisationVector/<k>`` in the HDF5 file), their values at the mesh's
vertices in the mesh's own order.
"""

import argparse
import logging
import pathlib

import dolfin as df
import numpy as np

from bar2d_contact import (
    DENSITY,
    LAME_LAMBDA,
    LAME_MU,
    LENGTHS,
    MASSES,
    SCHEMES,
    BarMatrices,
    Summary,
    stepped,
    scipy_of,
    time_step,
)

PARAMETERS = {"quadrature_degree": 2}


def to_scipy(form):
    """The matrix of a bilinear form assembled by legacy FEniCS (PETSc AIJ), as scipy CSR."""
    matrix = df.as_backend_type(df.assemble(form, form_compiler_parameters=PARAMETERS)).mat()
    return scipy_of(matrix)


class Bar(BarMatrices):
    """The bar at one level: legacy FEniCS's mesh, spaces and matrices, clamped dofs removed."""

    def __init__(self, level, mass):
        n1 = round(LENGTHS[0] * level)
        self.mesh = df.RectangleMesh.create(
            [df.Point(0.0, 0.0), df.Point(*LENGTHS)], [n1, level], df.CellType.Type.quadrilateral
        )
        self.vector_space = df.VectorFunctionSpace(self.mesh, "Lagrange", 1)
        self.scalar_space = df.FunctionSpace(self.mesh, "Lagrange", 1)
        h = LENGTHS[1] / level
        u = df.TrialFunction(self.vector_space)
        w = df.TestFunction(self.vector_space)

        def strain(f):
            return df.sym(df.grad(f))

        def stress(f):
            return 2.0 * LAME_MU * strain(f) + LAME_LAMBDA * df.tr(strain(f)) * df.Identity(2)

        stiffness = to_scipy(df.inner(stress(u), strain(w)) * df.dx)
        if mass == "standard":
            mass_dx = df.dx
        else:
            away = df.MeshFunction("size_t", self.mesh, 2, 0)
            for cell in df.cells(self.mesh):
                away[cell] = int(cell.midpoint().y() > 0.5 * h)
            mass_dx = df.dx(subdomain_data=away)(1)
        mass_matrix = to_scipy(DENSITY * df.inner(u, w) * mass_dx)

        nodes = self.scalar_space.tabulate_dof_coordinates()
        self.block = 2
        self.node_dofs = np.column_stack(
            [self.vector_space.sub(k).dofmap().dofs() for k in range(self.block)]
        )
        vector_nodes = self.vector_space.tabulate_dof_coordinates()
        for k in range(self.block):
            if not np.array_equal(vector_nodes[self.node_dofs[:, k]], nodes):
                raise RuntimeError("the vector and scalar Q1 spaces number the nodes differently")
        # Permute the vector dofs to node-major order (dof 2 node + k) for BarMatrices.
        order = self.node_dofs.reshape(-1)
        super().__init__(
            level,
            mass_matrix[order][:, order],
            stiffness[order][:, order],
            nodes,
            self.block,
        )

    def vector_values(self, values):
        """Free-dof values (node-major order) as the vector space's dof vector."""
        full = np.zeros(self.node_dofs.size)
        full[self.free] = values
        array = np.zeros(self.node_dofs.size)
        array[self.node_dofs.reshape(-1)] = full
        return array


def run(level, scheme, mass, out):
    """Steps the bar at LEVEL and writes every t_n with legacy FEniCS's XDMFFile; returns the
    run's summary line."""
    bar = Bar(level, mass)
    dt, _ = time_step(level)
    u_field = df.Function(bar.vector_space, name="displacement")
    v_field = df.Function(bar.vector_space, name="velocity")
    lam_field = df.Function(bar.scalar_space, name="contact_multiplier")
    summary = Summary(bar)
    path = out / f"fenics-bar2d-{scheme}-{mass}-level{level}.xdmf"
    with df.XDMFFile(bar.mesh.mpi_comm(), str(path)) as file:
        file.parameters["functions_share_mesh"] = True
        file.parameters["rewrite_function_mesh"] = False
        for n, displacement, velocity, multipliers in stepped(bar, scheme):
            summary.add(displacement, velocity, multipliers)
            u_field.vector().set_local(bar.vector_values(displacement))
            v_field.vector().set_local(bar.vector_values(velocity))
            lam = np.zeros(bar.scalar_space.dim())
            lam[bar.contact_nodes] = multipliers
            lam_field.vector().set_local(lam)
            for field in (u_field, v_field, lam_field):
                field.vector().apply("insert")
                file.write(field, n * dt)
    return summary.line(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--level", type=int, nargs="+", default=[10, 20])
    parser.add_argument("--scheme", choices=sorted(SCHEMES), default="crank-nicolson")
    parser.add_argument("--mass", choices=MASSES, default="standard")
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("target/fenics-runs"))
    args = parser.parse_args()
    if df.MPI.comm_world.size != 1:
        parser.error("runs on one process (the contact solve uses the whole matrices)")
    logging.getLogger("FFC").setLevel(logging.WARNING)
    logging.getLogger("UFL").setLevel(logging.WARNING)
    df.set_log_level(df.LogLevel.WARNING)
    args.out.mkdir(parents=True, exist_ok=True)
    for level in args.level:
        print(run(level, args.scheme, args.mass, args.out), flush=True)


if __name__ == "__main__":
    main()
