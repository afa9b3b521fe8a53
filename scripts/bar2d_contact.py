"""The 2D bar's data and its time stepping with an exact nodal contact solve, shared by the
scripts that solve it with another code's matrices (``dolfinx_bar2d.py``, ``fenics_bar2d.py``,
and ``getfem_bar2d.py --lcp``, which checks GetFEM's own steps against it): numpy and scipy only.
Not run by itself.

The discrete problem and the schemes are described in ``dolfinx_bar2d.py``'s docstring; a code's
script builds the mass and stiffness matrices of its space (Q1, or P1 on its triangles) and hands
them to :class:`BarMatrices`, then steps with :func:`stepped`.
"""

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

LENGTHS = (0.1, 1.0)
DENSITY = 1.0
LAME_LAMBDA = 0.25
LAME_MU = 0.5
GAP = 0.2
INITIAL_VELOCITY = -0.5
HORIZON = 2.0
RATIO = 2.0
SCHEMES = {
    "crank-nicolson": (0.25, 0.25, 0.5, 0.5),
    "backward-euler": (0.0, 1.0, 0.0, 1.0),
}
MASSES = ("standard", "redistributed")
COORDINATE_TOLERANCE = 1e-9


def scipy_of(matrix):
    """An assembled PETSc AIJ matrix (petsc4py, as DOLFINx and legacy FEniCS give it) as a scipy
    CSR matrix."""
    indptr, indices, values = matrix.getValuesCSR()
    return scipy.sparse.csr_matrix((values, indices, indptr), shape=matrix.getSize())


def solve_lcp(w, q):
    """μ ≥ 0 with y = q + W μ ≥ 0 and μᵀy = 0, by Murty's least-index principal pivoting.

    W is positive definite (a Delassus matrix), so the method ends after finitely many pivots
    with the unique solution; the active set's μ solves W_JJ μ_J = −q_J exactly and the other
    μ_i are 0, so μ_i y_i is 0 up to the round-off of that solve.
    """
    n = q.size
    scale = max(np.abs(q).max(), 1.0)
    active = np.zeros(n, dtype=bool)
    for _ in range(2**n + n + 1):
        mu = np.zeros(n)
        if active.any():
            mu[active] = np.linalg.solve(w[np.ix_(active, active)], -q[active])
        y = q + w @ mu
        violated = np.flatnonzero(
            (active & (mu < -1e-15 * scale)) | (~active & (y < -1e-15 * scale))
        )
        if violated.size == 0:
            mu[~active] = 0.0
            return mu
        active[violated[0]] = not active[violated[0]]
    raise RuntimeError("the contact LCP did not converge")


class BarMatrices:
    """The bar's matrices at one level with the clamped dofs removed, from a code's assembled
    mass and stiffness (scipy, over every dof), its nodes' coordinates and its dofs per node
    (dof ``block * node + k`` is component k of node ``node``)."""

    def __init__(self, level, mass_matrix, stiffness, nodes, block):
        self.level = level
        clamped_nodes = np.flatnonzero(np.abs(nodes[:, 1] - LENGTHS[1]) < COORDINATE_TOLERANCE)
        contact_nodes = np.flatnonzero(np.abs(nodes[:, 1]) < COORDINATE_TOLERANCE)
        self.contact_nodes = contact_nodes[np.argsort(nodes[contact_nodes, 0])]
        n_dofs = nodes.shape[0] * block
        clamped = np.zeros(n_dofs, dtype=bool)
        for k in range(block):
            clamped[block * clamped_nodes + k] = True
        self.free = np.flatnonzero(~clamped)
        position = np.full(n_dofs, -1)
        position[self.free] = np.arange(self.free.size)
        self.contact = position[block * self.contact_nodes + 1]
        self.mass = mass_matrix[self.free][:, self.free].tocsc()
        self.stiffness = stiffness[self.free][:, self.free].tocsc()
        self.dofs_with_mass = np.flatnonzero(np.abs(self.mass).sum(axis=1).A1 > 0.0)
        velocity = np.zeros(n_dofs)
        velocity[1::block] = INITIAL_VELOCITY
        self.initial_velocity = velocity[self.free]

    def initial_acceleration(self, displacement):
        """A⁰ from M_RR A_R = −(S U⁰)_R on the dofs with mass, 0 on the massless ones."""
        r = self.dofs_with_mass
        acceleration = np.zeros(self.free.size)
        m_rr = self.mass[r][:, r].tocsc()
        acceleration[r] = scipy.sparse.linalg.spsolve(m_rr, -(self.stiffness @ displacement)[r])
        return acceleration

    def energy(self, displacement, velocity):
        """½ VᵀMV + ½ UᵀSU with this run's mass."""
        return 0.5 * velocity @ (self.mass @ velocity) + 0.5 * displacement @ (
            self.stiffness @ displacement
        )


def time_step(level):
    """Δt = 1/(2 LEVEL) and the number of steps to T = 2."""
    dt = LENGTHS[1] / level / RATIO
    return dt, round(HORIZON / dt)


def stepped(bar, scheme):
    """Yields (n, U^n, V^n, λ^n) for n = 0 … N (free dofs; λ per contact node, ≤ 0): the one-step
    scheme SCHEME from U⁰ = 0, V⁰ = −0.5 e2, each step's contact solved exactly (an LCP on the
    Delassus matrix of the step matrix)."""
    a, b, c, d = SCHEMES[scheme]
    dt, steps = time_step(bar.level)
    step_matrix = (bar.mass / (b * dt * dt) + bar.stiffness).tocsc()
    solve = scipy.sparse.linalg.factorized(step_matrix)
    unit = np.zeros((bar.free.size, bar.contact.size))
    unit[bar.contact, np.arange(bar.contact.size)] = 1.0
    response = np.column_stack([solve(unit[:, k]) for k in range(bar.contact.size)])
    delassus = response[bar.contact]
    displacement = np.zeros(bar.free.size)
    velocity = bar.initial_velocity.copy()
    acceleration = bar.initial_acceleration(displacement)
    multipliers = np.zeros(bar.contact.size)
    yield 0, displacement, velocity, multipliers
    for n in range(1, steps + 1):
        predictor = displacement + dt * velocity + a * dt * dt * acceleration
        free = solve(bar.mass @ predictor / (b * dt * dt))
        mu = solve_lcp(delassus, free[bar.contact] + GAP)
        new_displacement = free + response @ mu
        new_acceleration = (new_displacement - predictor) / (b * dt * dt)
        velocity = velocity + dt * (c * acceleration + d * new_acceleration)
        displacement, acceleration, multipliers = new_displacement, new_acceleration, -mu
        yield n, displacement, velocity, multipliers


class Summary:
    """What a script prints of a run: the energy at t = 0 and t = T, the largest total contact
    force and the largest complementarity product."""

    def __init__(self, bar):
        self.bar = bar
        self.energies = []
        self.largest_force = 0.0
        self.complementarity = 0.0

    def add(self, displacement, velocity, multipliers):
        """One sample."""
        gaps = displacement[self.bar.contact] + GAP
        self.complementarity = max(self.complementarity, np.abs(gaps * multipliers).max())
        self.largest_force = max(self.largest_force, abs(multipliers.sum()))
        self.energies.append(self.bar.energy(displacement, velocity))

    def line(self, path):
        """The printed line of the run written to PATH."""
        return (
            f"{path}: {len(self.energies) - 1} steps, energy {self.energies[0]:.6e} → "
            f"{self.energies[-1]:.6e}, largest total contact force {self.largest_force:.4e}, "
            f"complementarity {self.complementarity:.1e}"
        )
