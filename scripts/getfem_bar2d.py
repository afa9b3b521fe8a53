#!/usr/bin/python3
"""GetFEM's solve of the note's 2D bar, written at every step with GetFEM's own VTU exporter.

Run with Debian's Python (``apt-get install -y python3-getfem``, GetFEM 5.4.2 with numpy and
scipy), from the repository (it imports ``scripts/bar2d_contact.py``):

    /usr/bin/python3 scripts/getfem_bar2d.py --level 10 20 --scheme crank-nicolson \\
        --mass standard --out target/getfem-vtu --check tests/data/getfem2d
    /usr/bin/python3 scripts/getfem_bar2d.py --level 10 20 40 80 --scheme crank-nicolson \\
        --mass standard --cell triangle --binary --lcp --out target/getfem-triangles

For each LEVEL it writes ``getfem-<scheme>-<mass>-nx<LEVEL>.pvd`` in OUT, a ParaView collection
of the ``4·LEVEL + 1`` snapshots ``getfem-<scheme>-<mass>-nx<LEVEL>/step-<n>.vtu`` (n = 0 … steps,
t_n = n Δt, the initial state first), for ``signorini verify scenes/bar2d.json RUN.pvd --code
getfem --code-version 5.4.2 --scheme <scheme> --mass <mass> --velocity velocity --multiplier
multiplier``.
``--binary`` writes GetFEM's binary snapshots instead of its ASCII ones (the files' stem then
ends in ``-binary``). ``--check DIR`` compares each run with GetFEM's earlier solve of the same
problem, ``DIR/getfem2d_<scheme>_<mass>_nx<LEVEL>.json.gz`` (format
``signorini-getfem2d-anchor/1``, see that directory's README.md), and prints the largest
differences. ``--lcp`` compares each run with the harness's one-step scheme and an exact nodal
contact solve on GetFEM's own matrices of the same mesh (below, "Checked"). ``--cell triangle``
solves on GetFEM's simplex mesh of the bar instead (below); its files are named
``getfem-triangle-<scheme>-<mass>-nx<LEVEL>…``, and they are verified on their own mesh (the
same ``verify`` command: the harness detects the triangles from the cells).

**The discrete problem** (that of ``tests/data/getfem2d/README.md``, the harness's
``scenes/bar2d.json``):

- the bar [0, 0.1] × [0, 1], ``LEVEL`` elements along x2 and ``round(0.1/h)`` across
  (h = 1/LEVEL), nodes at i·L/n (``gf.Mesh('cartesian', …)``); Q1 (``FEM_QK(2,1)``), 2×2 Gauss
  points (``IM_GAUSS_PARALLELEPIPED(2,3)``), plane strain, λ = 0.25, μ = 0.5, density 1;
- GetFEM's model object: ``add_isotropic_linearized_elasticity_brick`` on ``u``,
  ``add_mass_brick`` on ``Dot2_u`` (``--mass standard``: every element; ``--mass
  redistributed``: M^mod, the elements that do not touch x2 = 0, so both components of every
  contact node are massless), the face x2 = 1 clamped by
  ``add_Dirichlet_condition_with_simplification`` (its dofs eliminated);
- contact: ``add_nodal_contact_with_rigid_obstacle_brick`` on the face x2 = 0 with the
  obstacle ``y+0.2`` (signed distance; one constraint u2 + 0.2 ≥ 0 per node), the multiplier
  ``lambda_n`` (one per contact node, ≤ 0: the nodal force is −λ e2), Alart–Curnier's
  non-symmetric version (1), r = 10, solved by ``md.solve`` (Newton; GetFEM's default linear
  solver, MUMPS 5.5.1 in Debian's build) to a residual of 1e-13;
- time: ``--scheme crank-nicolson`` is ``add_Newmark_scheme('u', 1/4, 1/2)``, ``--scheme
  backward-euler`` is ``add_theta_method_for_second_order('u', 1)``; Δt = 1/(2·LEVEL), 4·LEVEL
  steps to T = 2; each step is one ``md.solve`` followed by
  ``shift_variables_for_time_integration``;
- initial data: ``Previous_u`` = U0 = 0, ``Previous_Dot_u`` = V0 = −0.5 e2 on every node off the
  clamped face and 0 on it, ``Previous_Dot2_u`` = A0 = 0 (A0 solves M_RR A_R = −(S U0)_R,
  which is 0 here; GetFEM's ``perform_init_time_derivative`` is not used).

**With** ``--cell triangle`` (another discrete problem than the scene's, on GetFEM's own mesh;
everything else above unchanged): ``gf.Mesh('regular simplices', x1, x2)`` on the same node
grid, each square cut into two triangles along the diagonal joining its two corners whose
indices i1 + i2 are even, so the diagonals alternate from square to square (DOLFINx's default
mesh, ``dolfinx_bar2d.py --cell triangle``, cuts every square along the same diagonal); P1
(``FEM_PK(2,1)``) for both spaces; the integration method ``IM_TRIANGLE(2)`` (3 points, exact for
polynomials of degree 2), the lowest of GetFEM's triangle rules that is exact for the P1 mass
(a product of two linear functions; the stiffness's integrand is constant on each cell):
measured at levels 10 and 80, its mass and stiffness matrices are ``IM_TRIANGLE(6)``'s to
6.5e-16 and 5.1e-16 of their largest entry, and the mass adds up to ρ·|Ω| = 0.1 to 3e-17. The
redistributed mass is GetFEM's own construction on its cells, not the harness's M^mod: the mass
brick over the triangles with no vertex on x2 = 0 (the same test as for Q1), so the massless
dofs are exactly both components of the contact nodes (checked at levels 20, 40, 80 against
the rows of the assembled mass; ``--lcp`` prints their number, 2·(n1 + 1)).

Each snapshot holds, as point data on the mesh's nodes: ``displacement`` (``u``),
``velocity`` (``Dot_u``, the scheme's velocity; V0 at t_0) and ``multiplier`` (``lambda_n``
placed on the contact nodes through a scalar Q1 (P1) ``MeshFem``, 0 elsewhere; 0 at t_0). The
multipliers are GetFEM's as its Newton leaves them: on steps without contact, values of order
1e-17 and below (``-2.77556e-17``) where an exact active set gives 0.

**What GetFEM writes** (``MeshFem.export_to_vtu(file, ['ascii'], mf_u, U, 'displacement',
mf_u, V, 'velocity', mf_scalar, Λ, 'multiplier')``, GetFEM 5.4.2's ``vtu_export``, read from
the files this script writes and from ``src/getfem/getfem_export.h`` of GetFEM 5.4.2):

- ``<?xml version="1.0"?>``, ``<VTKFile type="UnstructuredGrid" version="0.1"
  byte_order="LittleEndian">``, the comment ``<!--Exported by GetFEM-->``, one ``Piece``;
- ``Points``: ``Float32``, 3 components (x3 = 0), one point per node in GetFEM's dof order;
  ``Cells``: ``Int32`` ``connectivity``, ``offsets`` and ``types`` (9, VTK_QUAD; with ``--cell
  triangle`` 5, VTK_TRIANGLE, three nodes each);
- ``PointData``: ``Float32`` arrays; vectors with ``NumberOfComponents="3"`` (the third 0), the
  scalar without a ``NumberOfComponents`` attribute; no ``CellData``;
- ``'ascii'`` (the default here): ``format="ascii"``, every value written as a ``float`` by a C++
  stream at its default precision, i.e. 6 significant digits (``0.0209528``);
- without ``'ascii'`` (``--binary``): ``format="binary"``, inline base64 with no
  ``header_type`` attribute; each array is prefixed by a 4-byte header which for ``Points`` and
  ``Cells`` is the ``Int32`` byte count, but for ``PointData`` is a ``Float32`` holding the
  number of values given (44.0 for a 2-vector on 22 nodes, the bytes ``00 00 30 42``) rather
  than the byte count that follows (264);
- GetFEM writes no ``.pvd``: there is no collection writer in GetFEM 5.4.2 (neither in its Python
  interface nor in ``libgetfem``); this script writes the collection, one ``DataSet`` per step
  with ``timestep`` = n·Δt (Python's shortest round-trip repr) and ``part="0"``.

**Against GetFEM's earlier solve** of the same problem (``--check tests/data/getfem2d``),
levels 10 and 20, all four configurations, the largest
differences measured: 1.5e-14 in the contact nodes' u2 at every step, 2.9e-14 in the
multipliers at every step, 1.2e-14 in the displacement fields at t = 0.5, 1, 1.5, 2, and
3.5e-13 in the velocity at T (all four at Crank–Nicolson, standard mass, level 20; at most
7.1e-14 elsewhere). The files themselves hold the fields to Float32, in ASCII to 6 significant
digits.

**Checked against an exact contact solve** (``--lcp``): ``bar2d_contact.stepped``, the
harness's one-step scheme ((a, b, c, d) = (¼, ¼, ½, ½) for Newmark β = ¼, γ = ½, (0, 1, 0, 1)
for θ = 1) with each step's nodal contact solved exactly (Murty's pivoting on the Delassus
matrix), on the mass and stiffness matrices of the same ``mf_u`` assembled by GetFEM's
``asm_mass_matrix`` and ``asm_linear_elasticity`` with the same integration method; it checks
GetFEM's time integration and Alart–Curnier Newton, not its assembly. Largest differences over
every step, ``--cell triangle``, levels 10, 20, 40, 80: Crank–Nicolson with the standard mass,
which amplifies round-off with the level, displacement 6.7e-15, 2.7e-13, 1.0e-11, 4.1e-10,
velocity 1.8e-13, 1.0e-11, 7.4e-10, 5.0e-8, multipliers 7.6e-15, 3.6e-13, 2.5e-11, 7.1e-10 (on
the Q1 mesh at level 80: 2.2e-11, 4.0e-9, 3.9e-11); the other three configurations at most
3.4e-13, 1.6e-11 and 4.0e-14 (all at level 80).
"""

import argparse
import gzip
import json
import pathlib

import numpy as np
import scipy.sparse
import getfem as gf
from bar2d_contact import BarMatrices, stepped

LENGTHS = (0.1, 1.0)
LAME_LAMBDA = 0.25
LAME_MU = 0.5
DENSITY = 1.0
GAP = 0.2
INITIAL_VELOCITY = -0.5
HORIZON = 2.0
RATIO = 2.0
AUGMENTATION_R = 10.0
NEWTON_MAX_RES = 1e-13
NEWTON_MAX_ITER = 100

CONTACT, CLAMPED, AWAY = 1, 2, 3

# For each --cell: GetFEM's mesh of the node grid, its element and its integration method.
CELLS = {
    'quadrilateral': ('cartesian', 'FEM_QK(2,1)', 'IM_GAUSS_PARALLELEPIPED(2,3)'),
    'triangle': ('regular simplices', 'FEM_PK(2,1)', 'IM_TRIANGLE(2)'),
}


class Bar:
    """The 2D bar at one level: GetFEM's mesh of CELL elements, its vector and scalar spaces
    (Q1 or P1) and its model, ready to step."""

    def __init__(self, level, scheme, mass, cell='quadrilateral'):
        self.level = level
        self.mass = mass
        mesh_kind, fem_name, integration = CELLS[cell]
        n2 = level
        h = LENGTHS[1] / n2
        n1 = max(1, round(LENGTHS[0] / h))
        self.elements = (n1, n2)
        self.dt = 1.0 / (RATIO * level)
        self.steps = int(round(HORIZON / self.dt))
        x1 = [i * LENGTHS[0] / n1 for i in range(n1 + 1)]
        x2 = [i * LENGTHS[1] / n2 for i in range(n2 + 1)]
        m = gf.Mesh(mesh_kind, x1, x2)
        border = m.outer_faces()
        normals = m.normal_of_faces(border)
        m.set_region(CONTACT, border[:, np.nonzero(normals[1] < -0.5)[0]])
        m.set_region(CLAMPED, border[:, np.nonzero(normals[1] > 0.5)[0]])
        away = [cv for cv in m.cvid() if m.pts_from_cvid(cv)[0][1].min() > 0.5 * h]
        m.set_region(AWAY, np.array([away], dtype=np.int32))
        self.mesh = m

        fem = gf.Fem(fem_name)
        self.mf_u = gf.MeshFem(m, 2)
        self.mf_u.set_fem(fem)
        self.mf_scalar = gf.MeshFem(m, 1)
        self.mf_scalar.set_fem(fem)
        mim = gf.MeshIm(m, gf.Integ(integration))
        self.mim = mim

        md = gf.Model('real')
        md.add_fem_variable('u', self.mf_u)
        md.add_initialized_data('lambda', [LAME_LAMBDA])
        md.add_initialized_data('mu', [LAME_MU])
        md.add_isotropic_linearized_elasticity_brick(mim, 'u', 'lambda', 'mu')
        if scheme == 'crank-nicolson':
            md.add_Newmark_scheme('u', 0.25, 0.5)
        else:
            md.add_theta_method_for_second_order('u', 1.0)
        if mass == 'standard':
            md.add_mass_brick(mim, 'Dot2_u', repr(DENSITY))
        else:
            md.add_mass_brick(mim, 'Dot2_u', repr(DENSITY), AWAY)
        md.add_Dirichlet_condition_with_simplification('u', CLAMPED)
        contact_dofs = self.mf_u.basic_dof_on_region(CONTACT)
        self.contact_x_dofs = contact_dofs[0::2]
        md.add_variable('lambda_n', len(self.contact_x_dofs))
        md.add_initialized_data('r', [AUGMENTATION_R])
        md.add_nodal_contact_with_rigid_obstacle_brick(
            mim, 'u', 'lambda_n', 'r', CONTACT, 'y+%r' % GAP, 1)
        md.set_time_step(self.dt)
        self.model = md

        nd = self.mf_u.nbdof()
        v0 = np.zeros(nd)
        v0[1::2] = INITIAL_VELOCITY
        v0[self.mf_u.basic_dof_on_region(CLAMPED)] = 0.0
        md.set_variable('u', np.zeros(nd))
        md.set_variable('Previous_u', np.zeros(nd))
        md.set_variable('Previous_Dot_u', v0)
        md.set_variable('Previous_Dot2_u', np.zeros(nd))
        md.set_time(0.0)
        self.initial_velocity = v0

        # lambda_n's entries follow the contact nodes' x-dofs of mf_u; place them on the scalar
        # space's dofs at the same points.
        scalar_points = self.mf_scalar.basic_dof_nodes()
        scalar_dof = {tuple(p): i for i, p in enumerate(scalar_points.T)}
        u_points = self.mf_u.basic_dof_nodes()
        self.multiplier_dofs = np.array(
            [scalar_dof[tuple(u_points[:, d])] for d in self.contact_x_dofs], dtype=int)

    def matrices(self):
        """GetFEM's mass matrix (every cell, or the cells of AWAY for the redistributed mass) and
        stiffness matrix of ``mf_u`` by ``asm_mass_matrix`` and ``asm_linear_elasticity`` with the
        model's integration method, as scipy CSR matrices over every dof."""
        if self.mass == 'standard':
            mass = gf.asm_mass_matrix(self.mim, self.mf_u)
        else:
            mass = gf.asm_mass_matrix(self.mim, self.mf_u, self.mf_u, AWAY)
        ones = np.ones(self.mf_scalar.nbdof())
        stiffness = gf.asm_linear_elasticity(self.mim, self.mf_u, self.mf_scalar,
                                             LAME_LAMBDA * ones, LAME_MU * ones)
        return (scipy.sparse.csr_matrix(DENSITY * mass.full()),
                scipy.sparse.csr_matrix(stiffness.full()))

    def multiplier_field(self, lam):
        """The contact multipliers as a scalar nodal field: λ_i on the contact nodes, 0 elsewhere."""
        field = np.zeros(self.mf_scalar.nbdof())
        field[self.multiplier_dofs] = lam
        return field

    def states(self):
        """(n, t_n, U, V, λ) for n = 0 … steps: the initial state, then one GetFEM solve per step."""
        md = self.model
        nd = self.mf_u.nbdof()
        yield 0, 0.0, np.zeros(nd), self.initial_velocity.copy(), np.zeros(len(self.contact_x_dofs))
        for n in range(1, self.steps + 1):
            _, converged = md.solve('max_res', NEWTON_MAX_RES, 'max_iter', NEWTON_MAX_ITER)
            if not converged:
                raise RuntimeError('GetFEM Newton did not converge at step %d' % n)
            state = (n, n * self.dt, md.variable('u').copy(), md.variable('Dot_u').copy(),
                     md.variable('lambda_n').copy())
            md.shift_variables_for_time_integration()
            yield state

    def export(self, path, u, v, lam, binary):
        """One snapshot written by GetFEM's ``MeshFem.export_to_vtu``."""
        options = [] if binary else ['ascii']
        self.mf_u.export_to_vtu(str(path), *options, self.mf_u, u, 'displacement',
                                self.mf_u, v, 'velocity',
                                self.mf_scalar, self.multiplier_field(lam), 'multiplier')


def write_collection(path, entries):
    """A ParaView collection: one ``DataSet`` per (time, file), files relative to ``path``."""
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             '  <Collection>']
    for time, file in entries:
        lines.append('    <DataSet timestep="%r" group="" part="0" file="%s"/>' % (time, file))
    lines += ['  </Collection>', '</VTKFile>', '']
    path.write_text('\n'.join(lines))


def node_index(bar):
    """For each node of mf_u (dof pairs 2k, 2k+1), its index i1 + (n1 + 1)·i2."""
    n1, n2 = bar.elements
    points = bar.mf_u.basic_dof_nodes()[:, 0::2]
    i1 = np.rint(points[0] * n1 / LENGTHS[0]).astype(int)
    i2 = np.rint(points[1] * n2 / LENGTHS[1]).astype(int)
    return i1 + (n1 + 1) * i2


def by_node(bar, w):
    """A vector field of mf_u as [w1, w2] per node, in the order node = i1 + (n1 + 1)·i2."""
    out = np.zeros((len(w) // 2, 2))
    index = node_index(bar)
    out[index, 0] = w[0::2]
    out[index, 1] = w[1::2]
    return out


def compare(bar, run, anchor_path):
    """The largest differences between this run and GetFEM's earlier solve in ``anchor_path``."""
    with gzip.open(anchor_path, 'rt') as f:
        anchor = json.load(f)
    u_points = bar.mf_u.basic_dof_nodes()
    order = np.argsort(u_points[0][bar.contact_x_dofs], kind='stable')
    contact_u2 = np.array([u[bar.contact_x_dofs + 1][order] for _, _, u, _, _ in run])
    multipliers = np.array([lam[order] for _, _, _, _, lam in run])
    times = np.array([t for _, t, _, _, _ in run])
    history = anchor['history']
    fields = max(np.abs(by_node(bar, run[f['step']][2]) - np.array(f['displacement'])).max()
                 for f in anchor['fields'])
    return {
        'time': np.abs(times - np.array(history['time'])).max(),
        'contact_u2': np.abs(contact_u2 - np.array(history['contact_u2'])).max(),
        'multipliers': np.abs(multipliers - np.array(history['multipliers'])).max(),
        'fields': fields,
        'final_displacement': np.abs(by_node(bar, run[-1][2])
                                     - np.array(anchor['final']['displacement'])).max(),
        'final_velocity': np.abs(by_node(bar, run[-1][3])
                                 - np.array(anchor['final']['velocity'])).max(),
    }


def compare_with_lcp(bar, scheme, run):
    """The largest differences between this run and the harness's one-step scheme with an exact
    nodal LCP (``bar2d_contact.stepped``) on GetFEM's own matrices of the same mesh."""
    mass, stiffness = bar.matrices()
    nodes = bar.mf_u.basic_dof_nodes()[:, 0::2].T
    matrices = BarMatrices(bar.level, mass, stiffness, nodes, 2)
    u_points = bar.mf_u.basic_dof_nodes()
    order = np.argsort(u_points[0][bar.contact_x_dofs], kind='stable')
    largest = {'displacement': 0.0, 'velocity': 0.0, 'multipliers': 0.0}
    for (_, _, u, v, lam), (_, displacement, velocity, multipliers) in zip(
            run, stepped(matrices, scheme)):
        largest['displacement'] = max(largest['displacement'],
                                      np.abs(u[matrices.free] - displacement).max())
        largest['velocity'] = max(largest['velocity'],
                                  np.abs(v[matrices.free] - velocity).max())
        largest['multipliers'] = max(largest['multipliers'],
                                     np.abs(lam[order] - multipliers).max())
    largest['massless dofs'] = matrices.free.size - matrices.dofs_with_mass.size
    return largest


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--level', type=int, nargs='+', required=True)
    parser.add_argument('--scheme', choices=['crank-nicolson', 'backward-euler'], required=True)
    parser.add_argument('--mass', choices=['standard', 'redistributed'], required=True)
    parser.add_argument('--cell', choices=list(CELLS), default='quadrilateral',
                        help="GetFEM's mesh of the node grid: Q1 quadrilaterals (the scene's mesh) "
                        "or its regular simplices (P1 triangles)")
    parser.add_argument('--out', type=pathlib.Path, required=True)
    parser.add_argument('--binary', action='store_true',
                        help="GetFEM's binary (base64) snapshots instead of ASCII")
    parser.add_argument('--check', type=pathlib.Path, metavar='DIR',
                        help="compare with GetFEM's earlier solves in DIR")
    parser.add_argument('--lcp', action='store_true',
                        help="compare with the harness's scheme and an exact nodal LCP on "
                        "GetFEM's own matrices")
    args = parser.parse_args()
    if args.cell != 'quadrilateral' and args.check is not None:
        parser.error("--check compares with GetFEM's Q1 runs: only with --cell quadrilateral")

    for level in args.level:
        bar = Bar(level, args.scheme, args.mass, args.cell)
        code = 'getfem' if args.cell == 'quadrilateral' else 'getfem-%s' % args.cell
        stem = '%s-%s-%s-nx%d%s' % (code, args.scheme, args.mass, level,
                                    '-binary' if args.binary else '')
        steps_dir = args.out / stem
        steps_dir.mkdir(parents=True, exist_ok=True)
        entries = []
        run = []
        for n, t, u, v, lam in bar.states():
            name = 'step-%04d.vtu' % n
            bar.export(steps_dir / name, u, v, lam, args.binary)
            entries.append((t, '%s/%s' % (stem, name)))
            run.append((n, t, u, v, lam))
        write_collection(args.out / (stem + '.pvd'), entries)
        print('%s: %d snapshots' % (args.out / (stem + '.pvd'), len(entries)))
        if args.check:
            anchor = args.check / ('getfem2d_%s_%s_nx%d.json.gz' % (args.scheme, args.mass, level))
            for key, value in compare(bar, run, anchor).items():
                print('  max |this - %s| %s: %.3g' % (anchor.name, key, value))
        if args.lcp:
            for key, value in compare_with_lcp(bar, args.scheme, run).items():
                print('  max |this - exact LCP| %s: %.3g' % (key, value))


if __name__ == '__main__':
    main()
