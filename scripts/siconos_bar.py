#!/usr/bin/python3
"""Siconos's Moreau–Jean scheme on the 1D paper's Signorini–Dirichlet bar, as external runs.

Run with Debian's Python (python3-siconos, numpy):

    /usr/bin/python3 scripts/siconos_bar.py --nx 10 20 40 --out target/siconos-runs

For each NX it writes ``siconos-moreau-jean-nx<NX>.json`` in the harness's external-run format
``signorini-external/2`` (docs/src/external-runs.md), for ``signorini verify
scenes/bar1d-dirichlet.json``.

**The discrete problem** is the harness's for ``signorini run scenes/bar1d-dirichlet.json
--scheme moreau-jean --mass standard --nx NX`` (src/engine/fem/bar1d.rs,
src/engine/problem/bar.rs, src/harness/run/driver.rs):

- the bar [0, 1], ρ = c = 1 (E = 1), NX uniform P1 elements, nodes x_i = i h (h = 1/NX,
  x_NX = 1); the node x = 1 is clamped and removed from the unknowns, so dof i is node i,
  i = 0 … NX − 1, and dof 0 (x = 0) is the contact dof;
- the consistent mass M (element matrix h/6 [[2, 1], [1, 2]]) and the stiffness K (element
  matrix 1/h [[1, −1], [−1, 1]]), assembled as the harness does (same products, same sums);
- the obstacle at x = 0 with gap g = 0: y = q_0 + g ≥ 0; no load;
- U⁰, V⁰ the nodal values of the exact solution at t = 0 (``SignoriniDirichlet``, phase 0,
  τ = 0: u = ½ − x/2, u_t = 0);
- the harness's time grid: Δt = T / N, N = ⌈T ratio / h − 1e-9⌉ (``time_grid``), T = 3,
  ratio = Δx/Δt = 10.

**The scheme.** Siconos's ``MoreauJeanOSI`` (θ = ½) on a ``LagrangianLinearTIDS`` (M, K, no
damping, no load), with a ``LagrangianLinearTIR`` y = H q, H = e_0ᵀ, a ``NewtonImpactNSL``
(e = 0) and an ``LCP`` one-step nonsmooth problem (Siconos's default solver, Lemke), stepped by
``TimeStepping``; with h the time step Δt:

    M (v_{k+1} − v_k) = −h K q_{k+θ} + Hᵀ p_{k+1},   q_{k+1} = q_k + h v_{k+θ},
    x_{k+θ} = (1 − θ) x_k + θ x_{k+1};
    active when y_k + ½ h ẏ_k ≤ 0 (MoreauJeanOSI::addInteractionInIndexSet, γ = ½):
        0 ≤ ẏ_{k+1} + e ẏ_k ⟂ p_{k+1} ≥ 0;   otherwise p_{k+1} = 0.

Siconos solves it as W v_free = M v_k − h K q_k − h²θ(1 − θ) K v_k with W = M + h²θ² K, the
LCP on H W⁻¹ Hᵀ, then v_{k+1} = v_free + W⁻¹ Hᵀ p_{k+1} and the position update above.
The index set of step k → k + 1 is updated from (q_k, v_k) at the end of the previous step
(at initialisation for the first).

**The harness's conventions** (src/engine/schemes/moreau_jean.rs, eqs. MJ-a–d) are the same
equations with U = q, V = v, S = K, B = H, F = 0 and the contact entering as −Δt Bᵀλ^{n+1}:

    λ^{n+1} = −p_{k+1} / Δt ≤ 0,

the force of the step's impulse, reported at t_{n+1}. Sample n is the state after n steps
(t_n = n Δt, the harness's ``time()``). Siconos computes no impulse before the first step, so
``lambda`` is null at t = 0. ``energy`` is Siconos's kinetic energy
(``computeKineticEnergy``, ½ vᵀMv) plus ½ qᵀKq with the system's own K: ``total-at-sample``.
"""

import argparse
import json
import math
import pathlib
import subprocess

import numpy as np
import siconos
import siconos.kernel as sk

SCENE = "bar1d-dirichlet"  # scenes/bar1d-dirichlet.json
LENGTH = 1.0
DENSITY = 1.0
WAVE_SPEED = 1.0
GAP = 0.0
HORIZON = 3.0
RATIO = 10.0
THETA = 0.5
RESTITUTION = 0.0
LABEL = "Siconos MoreauJeanOSI, standard mass"
CONTACT = "Siconos MoreauJeanOSI + NewtonImpactNSL e=0, LCP (Lemke)"


def siconos_version():
    """The installed python3-siconos's upstream version (Debian's 4.4.0+dfsg-2 gives 4.4.0).

    Debian's build reports ``siconos.version`` as 4.5.0, so the package's version is read first.
    """
    try:
        query = ["dpkg-query", "-W", "-f=${Version}", "python3-siconos"]
        version = subprocess.run(query, capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return siconos.version
    return version.split("+")[0].split("-")[0] or siconos.version


def nodes(nx):
    """The nodes x_i = i h, the last one exactly L (``Bar1d::node``)."""
    h = LENGTH / nx
    return [i * h for i in range(nx)] + [LENGTH]


def assemble(nx, element):
    """The clamped bar's matrix from a 2×2 element matrix: dof i = node i, node NX removed."""
    matrix = np.zeros((nx, nx))
    for e in range(nx):
        for a, i in enumerate((e, e + 1)):
            for b, j in enumerate((e, e + 1)):
                if i < nx and j < nx:
                    matrix[i, j] += element[a][b]
    return matrix


def mass_and_stiffness(nx):
    """The consistent mass ρh/6 [[2, 1], [1, 2]] and the stiffness E/h [[1, −1], [−1, 1]]."""
    h = LENGTH / nx
    m = DENSITY * h / 6.0
    k = DENSITY * WAVE_SPEED * WAVE_SPEED / h
    mass = assemble(nx, [[2.0 * m, m], [m, 2.0 * m]])
    stiffness = assemble(nx, [[k, -k], [-k, k]])
    return mass, stiffness


def initial_state(nx):
    """U⁰, V⁰: the exact solution at t = 0 at the free nodes (u = ½ − x/2, u_t = 0)."""
    x = nodes(nx)[:nx]
    return np.array([0.5 - 0.5 * xi for xi in x]), np.zeros(nx)


def time_grid(nx):
    """The harness's steps N = ⌈T ratio / h − 1e-9⌉ and Δt = T / N (``run::time_grid``)."""
    steps = max(math.ceil(HORIZON / (LENGTH / nx / RATIO) - 1e-9), 1)
    return steps, HORIZON / steps


def simulation(nx, dt, steps):
    """The Siconos model of the bar: its system, its interaction and the time stepping."""
    mass, stiffness = mass_and_stiffness(nx)
    q0, v0 = initial_state(nx)
    bar = sk.LagrangianLinearTIDS(q0, v0, mass)
    bar.setKPtr(stiffness)
    measure = np.zeros((1, nx))
    measure[0, 0] = 1.0
    contact = sk.Interaction(
        sk.NewtonImpactNSL(RESTITUTION),
        sk.LagrangianLinearTIR(measure, np.array([GAP])),
    )
    system = sk.NonSmoothDynamicalSystem(0.0, steps * dt)
    system.insertDynamicalSystem(bar)
    system.link(contact, bar)
    stepping = sk.TimeStepping(
        system, sk.TimeDiscretisation(0.0, dt), sk.MoreauJeanOSI(THETA), sk.LCP()
    )
    return stepping, bar, contact


def sample(n, dt, bar, lam):
    """Sample n: the nodal fields with the clamped node's 0, λ and the energy."""
    q, v = bar.q(), bar.velocity()
    elastic = 0.5 * float(q @ (bar.K() @ q))
    return {
        "time": n * dt,
        "displacement": [float(x) for x in q] + [0.0],
        "velocity": [float(x) for x in v] + [0.0],
        "lambda": lam,
        "energy": bar.computeKineticEnergy() + elastic,
    }


def integrate(nx):
    """Every step of the run on NX elements, as samples."""
    steps, dt = time_grid(nx)
    stepping, bar, contact = simulation(nx, dt, steps)
    samples = [sample(0, dt, bar, None)]
    for n in range(1, steps + 1):
        stepping.computeOneStep()
        impulse = float(contact.lambda_(1)[0])
        samples.append(sample(n, dt, bar, -impulse / dt))
        stepping.nextStep()
    return samples


def run_file(nx, samples, version):
    """The ``signorini-external/2`` object of one run."""
    return {
        "format": "signorini-external/2",
        "scene": SCENE,
        "code": {"name": "siconos", "version": version},
        "label": LABEL,
        "scheme": f"moreau-jean(theta={THETA},e={RESTITUTION})",
        "mass": "standard",
        "contact": CONTACT,
        "energy_definition": "total-at-sample",
        "mesh": {"nodes": nodes(nx)},
        "samples": samples,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument(
        "--nx", type=int, nargs="+", action="extend", required=True,
        help="number of elements (several: --nx 10 20 40, or --nx repeated)",
    )
    parser.add_argument("--out", type=pathlib.Path, required=True, help="output directory")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    version = siconos_version()
    for nx in args.nx:
        path = args.out / f"siconos-moreau-jean-nx{nx}.json"
        with path.open("w") as f:
            json.dump(run_file(nx, integrate(nx), version), f, separators=(",", ":"))
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
