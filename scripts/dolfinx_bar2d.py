#!/usr/bin/python3
"""DOLFINx's matrices of the 2D bar (``scenes/bar2d.json``), stepped with an exact nodal contact
solve and written every step with ``dolfinx.io.VTKFile`` (or ``XDMFFile``), as external runs.

Run with Debian's Python (python3-dolfinx 0.5.2, numpy, scipy):

    apt-get install -y python3-dolfinx
    /usr/bin/python3 scripts/dolfinx_bar2d.py --level 10 20 --scheme crank-nicolson \
        --mass standard --out target/dolfinx-runs --getfem tests/data/getfem2d

For each LEVEL it writes the ParaView collection
``dolfinx-bar2d-<scheme>-<mass>-level<LEVEL>.pvd`` (and the files it points to) in OUT (with
``--writer xdmf``: ``….xdmf`` and its ``….h5``), meant
(issue 52) for ``signorini verify scenes/bar2d.json RUN.pvd --code dolfinx --code-version 0.5.2 --scheme
<scheme> --mass <mass> --velocity velocity --multiplier contact_multiplier``. It prints one line
per run: the steps, the energy at t = 0 and t = T, the largest total contact force and the
largest complementarity product; with ``--getfem DIR`` (GetFEM's runs of the same problem,
tests/data/getfem2d) also the largest differences from GetFEM's run of the same
scheme, mass and level: the contact nodes' u2 and multipliers and the total force at every
step, every node's displacement and velocity at T.

**Checked** at levels 10 and 20, both schemes, both masses (largest differences over every
step, all in Crank–Nicolson with the standard mass at level 20, which amplifies round-off; the
largest of the other seven runs in brackets). Against GetFEM (``--getfem``): contact u2
2.8e-13 (2.9e-14), multipliers 5.5e-13 (1.4e-14), total force 1.2e-12 (2.4e-14),
displacement at T 1.7e-13 (1.1e-14), velocity at T 6.1e-12 (5.6e-13). Against ``signorini run
scenes/bar2d.json --scheme S --mass M --nx LEVEL --fields-every-step`` (its .vtu and the files
written here read back, the latter through .pvd → .pvtu → _p0_ .vtu, nodes matched by
coordinates): displacement of every node 1.8e-13 (2.2e-14), velocity 7.6e-12 (3.1e-13), total
force 6.5e-13 (4.5e-15).

**The discrete problem** is the harness's ``signorini run scenes/bar2d.json --scheme <scheme>
--mass <mass> --nx LEVEL`` and GetFEM's (tests/data/getfem2d/README.md):

- the bar [0, 0.1] × [0, 1], ``dolfinx.mesh.create_rectangle`` with ``CellType.quadrilateral``,
  LEVEL elements along x2 and round(0.1 LEVEL) across; the space Q1 (``VectorFunctionSpace``
  ("Lagrange", 1)) (with ``--cell triangle``: DOLFINx's default triangles, each square cut along
  one diagonal, P1 on the same nodes, files named ``dolfinx-bar2d-triangle-…``: another discrete
  problem than the scene's, verified on its own mesh), plane strain σ = 2μ ε(u) + λ tr ε(u) I with λ = 0.25, μ = 0.5, density 1;
  the forms integrated with 2 × 2 Gauss points (``quadrature_degree`` 2) and assembled by
  ``dolfinx.fem.petsc.assemble_matrix`` without boundary conditions, then read into scipy;
- the mass ``standard`` (consistent, over every cell) or ``redistributed`` (the paper's M^mod:
  over the cells that do not touch x2 = 0, so both components of every contact node are
  massless), the stiffness S;
- the face x2 = 1 clamped: its dofs are removed from the unknowns (kept at 0 in the files);
- the rigid obstacle 0.2 below the face x2 = 0: one constraint per node of that face on its
  u2 dof, u2 + 0.2 ≥ 0, nodal force −λ e2 with λ ≤ 0, u2 + 0.2 = 0 where λ < 0;
- Δt = 1/(2 LEVEL) (ratio Δx/Δt = 2), 4 LEVEL steps to T = 2; U⁰ = 0, V⁰ = −0.5 e2 on every
  node off the clamped face (0 on it), A⁰ from M_RR A_R = −(S U⁰)_R (so A⁰ = 0).

**The schemes** are the harness's one-step form (src/engine/schemes/one_step.rs):

    U^{n+1} = U^n + Δt V^n + Δt² (a A^n + b A^{n+1})
    V^{n+1} = V^n + Δt (c A^n + d A^{n+1})
    M A^{n+1} + S U^{n+1} = −Bᵀλ^{n+1},   0 ≤ B U^{n+1} + g ⟂ λ^{n+1} ≤ 0

with (a, b, c, d) = (¼, ¼, ½, ½) for ``crank-nicolson`` (Newmark β = ¼, γ = ½) and (0, 1, 0, 1)
for ``backward-euler`` (θ = 1). Each step solves (M / (bΔt²) + S) U^{n+1} = M P / (bΔt²) −
Bᵀλ^{n+1}, P = U^n + ΔtV^n + aΔt²A^n, by one sparse LU of the step matrix: the free solve
U_free, the Delassus matrix W = B (M / (bΔt²) + S)⁻¹ Bᵀ, and the linear complementarity
problem μ = −λ ≥ 0, y = B U_free + g + W μ ≥ 0, μᵀy = 0 on the contact dofs, solved exactly
by Murty's least-index principal pivoting (finite for the positive definite W). Then
A^{n+1} = (U^{n+1} − P) / (bΔt²) and V^{n+1} from the second line, on every dof (massless
ones included). The multiplier at t = 0 is 0 (the bar starts 0.2 above the obstacle).

**What DOLFINx 0.5.2 writes** (``VTKFile(comm, path, "w").write_function([u, v, lam], t)`` at
every t_n = n Δt, n = 0 … 4 LEVEL, on one process; the files are left as DOLFINx wrote them):

- ``<stem>.pvd``: ``<VTKFile type="Collection" version="1.0">`` with no ``byte_order``; one
  ``<DataSet timestep="…" part="0" file="<stem>NNNNNN.pvtu" />`` per write, the time printed
  with 17 significant digits (``0.050000000000000003``);
- ``<stem>NNNNNN.pvtu``: a ``PUnstructuredGrid`` (version 1.0, no ``byte_order``,
  ``GhostLevel="1"``) even on one process, whose ``Piece Source="<stem>_p0_NNNNNN.vtu"`` is
  listed once per function written (three times here) for the same piece; its ``PPointData``
  declares ``vtkOriginalPointIds`` (Int64), ``vtkGhostType`` (UInt8), ``displacement`` and
  ``velocity`` (Float64, ``NumberOfComponents="3"``) and ``contact_multiplier`` (Float64,
  ``NumberOfComponents="0"``);
- ``<stem>_p0_NNNNNN.vtu``: an ``UnstructuredGrid`` of version ``2.2`` with no ``byte_order``
  and no ``header_type``, every array inline ASCII (``format="ascii"``), the doubles printed
  with 16 significant digits (not always the bits DOLFINx held); the points in DOLFINx's own
  order (not x1-fastest), Float64 with three components (x3 = 0), off the grid by up to
  1.1e-16 (``0.2000000000000001``, ``1.110223024625157e-17`` for 0); cells of VTK type 70
  (Lagrange quadrilateral) with Int32 connectivity and offsets; cell data ``vtkGhostType``
  and ``vtkOriginalCellIds``; ``<PointData Vectors="velocity"
  Scalars="contact_multiplier">`` with ``vtkOriginalPointIds``, ``vtkGhostType``, then the
  functions by their names: ``displacement`` and ``velocity`` padded to three components (the
  third 0), ``contact_multiplier`` one component with no ``NumberOfComponents`` attribute
  (λ_i ≤ 0 on the contact nodes, 0 elsewhere).

**What DOLFINx 0.5.2's XDMFFile writes** (``--writer xdmf``: ``write_mesh`` once, then
``write_function(f, t)`` for each of the three functions at every t_n): ``<stem>.xdmf``, XDMF 3
with an empty ``DOCTYPE``; a grid ``mesh`` (``Quadrilateral`` topology, ``XY`` geometry at
``/Mesh/mesh/geometry``), then one temporal collection per function, named by it, whose grids
``xi:include`` the mesh's topology and geometry, carry ``<Time Value="…"/>`` (17 significant
digits) and the function as a nodal ``Attribute`` at ``/Function/<name>/<time with _ for .>``
in ``<stem>.h5``: ``Float64``, vectors padded to three components, the values at the
geometry's nodes in its order.
"""

import argparse
import gzip
import json
import logging
import pathlib

import numpy as np
import ufl
from mpi4py import MPI

import dolfinx
import dolfinx.fem
import dolfinx.fem.petsc
import dolfinx.io
import dolfinx.mesh
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

QUADRATURE = {"quadrature_degree": 2}
WRITERS = {"vtk": "pvd", "xdmf": "xdmf"}
CELLS = {
    "quadrilateral": dolfinx.mesh.CellType.quadrilateral,
    "triangle": dolfinx.mesh.CellType.triangle,
}


def to_scipy(form):
    """The matrix of a bilinear form assembled by DOLFINx (PETSc AIJ), as a scipy CSR matrix."""
    matrix = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(form))
    matrix.assemble()
    return scipy_of(matrix)


class Bar(BarMatrices):
    """The bar at one level: DOLFINx's mesh, spaces and matrices, with the clamped dofs removed."""

    def __init__(self, level, mass, cell="quadrilateral"):
        n1 = round(LENGTHS[0] * level)
        self.mesh = dolfinx.mesh.create_rectangle(
            MPI.COMM_WORLD,
            [np.array([0.0, 0.0]), np.array(LENGTHS)],
            [n1, level],
            CELLS[cell],
        )
        self.vector_space = dolfinx.fem.VectorFunctionSpace(self.mesh, ("Lagrange", 1))
        self.scalar_space = dolfinx.fem.FunctionSpace(self.mesh, ("Lagrange", 1))
        h = LENGTHS[1] / level

        u = ufl.TrialFunction(self.vector_space)
        w = ufl.TestFunction(self.vector_space)
        gdim = self.mesh.geometry.dim

        def strain(f):
            return ufl.sym(ufl.grad(f))

        def stress(f):
            return 2.0 * LAME_MU * strain(f) + LAME_LAMBDA * ufl.tr(strain(f)) * ufl.Identity(gdim)

        dx = ufl.Measure("dx", domain=self.mesh, metadata=QUADRATURE)
        stiffness = to_scipy(ufl.inner(stress(u), strain(w)) * dx)
        if mass == "standard":
            mass_dx = dx
        else:
            tdim = self.mesh.topology.dim
            away = dolfinx.mesh.locate_entities(self.mesh, tdim, lambda x: x[1] > 0.5 * h)
            tags = dolfinx.mesh.meshtags(
                self.mesh, tdim, away, np.ones(away.size, dtype=np.int32)
            )
            mass_dx = ufl.Measure(
                "dx", domain=self.mesh, subdomain_data=tags, metadata=QUADRATURE
            )(1)
        mass_matrix = to_scipy(DENSITY * ufl.inner(u, w) * mass_dx)

        nodes = self.scalar_space.tabulate_dof_coordinates()
        if not np.array_equal(self.vector_space.tabulate_dof_coordinates(), nodes):
            raise RuntimeError("the vector and scalar spaces number the nodes differently")
        block = self.vector_space.dofmap.index_map_bs
        super().__init__(level, mass_matrix, stiffness, nodes, block)


def run(level, scheme, mass, out, getfem, writer, cell):
    """Steps the bar at LEVEL on CELL elements and writes every t_n with WRITER; returns a
    summary (and the differences from GetFEM's run in the directory GETFEM unless it is None)."""
    bar = Bar(level, mass, cell)
    dt, _ = time_step(level)
    u_field = dolfinx.fem.Function(bar.vector_space)
    u_field.name = "displacement"
    v_field = dolfinx.fem.Function(bar.vector_space)
    v_field.name = "velocity"
    lam_field = dolfinx.fem.Function(bar.scalar_space)
    lam_field.name = "contact_multiplier"
    summary = Summary(bar)
    history = []
    stem = f"dolfinx-bar2d-{scheme}-{mass}-level{level}"
    if cell != "quadrilateral":
        stem = f"dolfinx-bar2d-{cell}-{scheme}-{mass}-level{level}"
    path = out / f"{stem}.{WRITERS[writer]}"
    with open_writer(writer, bar.mesh, path) as file:
        for n, displacement, velocity, multipliers in stepped(bar, scheme):
            summary.add(displacement, velocity, multipliers)
            history.append((displacement[bar.contact].copy(), multipliers.copy()))
            u_field.x.array[:] = 0.0
            u_field.x.array[bar.free] = displacement
            v_field.x.array[:] = 0.0
            v_field.x.array[bar.free] = velocity
            lam_field.x.array[:] = 0.0
            lam_field.x.array[bar.contact_nodes] = multipliers
            write_fields(writer, file, [u_field, v_field, lam_field], n * dt)
    if getfem is None:
        return summary.line(path)
    final = (u_field, v_field)
    return summary.line(path) + "\n  " + compare_with_getfem(bar, scheme, mass, history, final, getfem)


def open_writer(writer, mesh, path):
    """DOLFINx's file for WRITER (``vtk``: ``VTKFile``; ``xdmf``: ``XDMFFile`` with the mesh
    written first, as DOLFINx's demos do)."""
    if writer == "vtk":
        return dolfinx.io.VTKFile(mesh.comm, str(path), "w")
    file = dolfinx.io.XDMFFile(mesh.comm, str(path), "w")
    file.write_mesh(mesh)
    return file


def write_fields(writer, file, fields, time):
    """One time's FIELDS: VTKFile takes them in one call, XDMFFile one function per call."""
    if writer == "vtk":
        file.write_function(fields, time)
        return
    for field in fields:
        file.write_function(field, time)


def compare_with_getfem(bar, scheme, mass, history, final, directory):
    """The largest differences from GetFEM's run of the same configuration (its README's format):
    the contact nodes' u2 and multipliers and the total force at every step, the displacement
    and velocity of every node at T."""
    path = directory / f"getfem2d_{scheme}_{mass}_nx{bar.level}.json.gz"
    with gzip.open(path, "rt") as file:
        getfem = json.load(file)
    rows = getfem["history"]
    if len(rows["time"]) != len(history):
        raise SystemExit(f"{path}: {len(rows['time'])} samples, this run {len(history)}")
    u2 = max(
        np.abs(ours - np.array(theirs)).max()
        for (ours, _), theirs in zip(history, rows["contact_u2"])
    )
    multiplier = max(
        np.abs(ours - np.array(theirs)).max()
        for (_, ours), theirs in zip(history, rows["multipliers"])
    )
    force = max(
        abs(ours.sum() - theirs) for (_, ours), theirs in zip(history, rows["total_force"])
    )
    nodes = bar.scalar_space.tabulate_dof_coordinates()[:, :2]
    h = np.array([LENGTHS[0] / round(LENGTHS[0] * bar.level), LENGTHS[1] / bar.level])
    grid = np.rint(nodes / h).astype(int)
    order = np.lexsort((grid[:, 0], grid[:, 1]))
    fields = []
    for field, name in zip(final, ("displacement", "velocity")):
        ours = field.x.array.reshape(-1, 2)[order]
        fields.append(np.abs(ours - np.array(getfem["final"][name])).max())
    return (
        f"vs {path.name}: contact u2 {u2:.2e}, multipliers {multiplier:.2e}, total force "
        f"{force:.2e} (every step); displacement {fields[0]:.2e}, velocity {fields[1]:.2e} (at T)"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--level", type=int, nargs="+", default=[10, 20])
    parser.add_argument("--scheme", choices=sorted(SCHEMES), default="crank-nicolson")
    parser.add_argument("--mass", choices=MASSES, default="standard")
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("target/dolfinx-runs"))
    parser.add_argument(
        "--getfem",
        type=pathlib.Path,
        help="compare with GetFEM's runs there (getfem2d_<scheme>_<mass>_nx<LEVEL>.json.gz)",
    )
    parser.add_argument(
        "--writer",
        choices=sorted(WRITERS),
        default="vtk",
        help="dolfinx.io.VTKFile (a .pvd series) or dolfinx.io.XDMFFile (.xdmf with .h5)",
    )
    parser.add_argument(
        "--cell",
        choices=sorted(CELLS),
        default="quadrilateral",
        help="the cells of create_rectangle: Q1 quadrilaterals (the scene's mesh) or DOLFINx's "
        "default triangles (each square cut along one diagonal, P1)",
    )
    args = parser.parse_args()
    if args.cell != "quadrilateral" and args.getfem is not None:
        parser.error("--getfem compares with GetFEM's Q1 runs: only with --cell quadrilateral")
    if MPI.COMM_WORLD.size != 1:
        parser.error("runs on one process (the contact solve uses the whole matrices)")
    logging.getLogger().setLevel(logging.WARNING)
    args.out.mkdir(parents=True, exist_ok=True)
    for level in args.level:
        print(
            run(level, args.scheme, args.mass, args.out, args.getfem, args.writer, args.cell),
            flush=True,
        )


if __name__ == "__main__":
    main()
