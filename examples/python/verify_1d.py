#!/usr/bin/env python3
"""A small contact code of one's own, written to be verified by `signorini verify`.

It solves the 1D paper's Signorini-Dirichlet benchmark (Dabaghi, Petrov, Pousin, Renard,
hal-00917450, 2013, section 5.1): the bar [0, 1] with density 1 and wave speed 1, clamped at
x = 1, the obstacle at x = 0,

    u_tt - u_xx = 0,   u(1, t) = 0,   u(0, t) >= 0,  lambda = u_x(0, t) <= 0,  u(0, t) lambda = 0,
    u(x, 0) = 1/2 - x/2,   u_t(x, 0) = 0,   0 <= t <= T = 3,

with P1 finite elements on NX elements, the consistent ("standard") mass matrix M and the
stiffness S, and a one-step scheme in time with the paper's ratio dx/dt = 10 (eqs. 32, 34):

    M A^{n+1} + S U^{n+1} = -lambda^{n+1} e_0,   0 <= U^{n+1}_0  _|_  lambda^{n+1} <= 0,
    U^{n+1} = U^n + dt V^n + dt^2 (a A^n + b A^{n+1}),   V^{n+1} = V^n + dt (c A^n + d A^{n+1}),

Crank-Nicolson (Newmark, beta = 1/4, gamma = 1/2): (a, b, c, d) = (1/4, 1/4, 1/2, 1/2);
backward Euler (theta = 1): (a, b, c, d) = (0, 1, 0, 1). Eliminating A^{n+1} leaves
K U^{n+1} = r^n - lambda^{n+1} e_0 with K = M / (b dt^2) + S: the free solution U* = K^{-1} r^n
and w = K^{-1} e_0 give U^{n+1} = U* - lambda w, and the one contact node's condition is solved
exactly by lambda = min(0, U*_0 / w_0).

Each level is written as one `signorini-external/2` JSON file: every step's displacement,
velocity and multiplier, with the scheme and mass declared, so that signorini computes the
energy norms with its own M and reruns the same scheme to compare step by step.

Usage: python3 verify_1d.py SCHEME OUT_DIR [NX ...]
SCHEME is crank-nicolson or backward-euler; the levels are 10 20 40 80 by default.
Plain Python 3, no third-party module.
"""

import json
import os
import sys

LENGTH = 1.0
HORIZON = 3.0
RATIO = 10.0  # dx / dt, the 1D paper's ratio for this benchmark

# The one-step form's coefficients (a, b, c, d) and the label of each scheme.
SCHEMES = {
    "crank-nicolson": ((0.25, 0.25, 0.5, 0.5), "Crank-Nicolson, standard mass"),
    "backward-euler": ((0.0, 1.0, 0.0, 1.0), "backward Euler, standard mass"),
}


def tridiagonal_factor(diag, off):
    """The LDL^T factors of the symmetric tridiagonal matrix (diag, off)."""
    d = [diag[0]]
    l = []
    for i in range(1, len(diag)):
        l.append(off[i - 1] / d[i - 1])
        d.append(diag[i] - l[-1] * off[i - 1])
    return d, l


def tridiagonal_solve(factors, rhs):
    """x with (diag, off) x = rhs, from tridiagonal_factor's factors."""
    d, l = factors
    y = list(rhs)
    for i in range(1, len(y)):
        y[i] -= l[i - 1] * y[i - 1]
    x = [yi / di for yi, di in zip(y, d)]
    for i in range(len(x) - 2, -1, -1):
        x[i] -= l[i] * x[i + 1]
    return x


def tridiagonal_product(diag, off, x):
    """(diag, off) x for a symmetric tridiagonal matrix."""
    y = [diag[i] * x[i] for i in range(len(x))]
    for i in range(len(x) - 1):
        y[i] += off[i] * x[i + 1]
        y[i + 1] += off[i] * x[i]
    return y


def solve(scheme, nx):
    """The scheme on nx elements: the sample times, U, V and lambda at every step."""
    (ca, cb, cc, cd), _ = SCHEMES[scheme]
    h = LENGTH / nx
    dt = h / RATIO
    steps = round(HORIZON / dt)
    # Unknowns: the nodes x_0 = 0 ... x_{NX-1}; x_NX = 1 is clamped.
    m_diag = [h / 3.0] + [2.0 * h / 3.0] * (nx - 1)
    m_off = [h / 6.0] * (nx - 1)
    s_diag = [1.0 / h] + [2.0 / h] * (nx - 1)
    s_off = [-1.0 / h] * (nx - 1)
    c = 1.0 / (cb * dt * dt)
    k_factors = tridiagonal_factor(
        [c * m + s for m, s in zip(m_diag, s_diag)],
        [c * m + s for m, s in zip(m_off, s_off)],
    )
    w = tridiagonal_solve(k_factors, [1.0] + [0.0] * (nx - 1))

    u = [0.5 - 0.5 * (i * h) for i in range(nx)]
    v = [0.0] * nx
    lam = 0.0  # u(0, 0) = 1/2 > 0: no contact at the start
    # M A^0 = -S U^0 - lambda^0 e_0
    a = tridiagonal_solve(
        tridiagonal_factor(m_diag, m_off),
        [-f for f in tridiagonal_product(s_diag, s_off, u)],
    )
    times, us, vs, lams = [0.0], [u + [0.0]], [v + [0.0]], [lam]
    for n in range(1, steps + 1):
        predictor = [ui + dt * vi + ca * dt * dt * ai for ui, vi, ai in zip(u, v, a)]
        rhs = tridiagonal_product(m_diag, m_off, [c * p for p in predictor])
        free = tridiagonal_solve(k_factors, rhs)
        lam = min(0.0, free[0] / w[0])
        u_new = [fi - lam * wi for fi, wi in zip(free, w)]
        a_new = [c * (un - p) for un, p in zip(u_new, predictor)]
        v = [vi + dt * (cc * ai + cd * an) for vi, ai, an in zip(v, a, a_new)]
        u, a = u_new, a_new
        times.append(n * dt)
        us.append(u + [0.0])
        vs.append(v + [0.0])
        lams.append(lam)
    return times, us, vs, lams


def run_file(scheme, nx):
    """The signorini-external/2 document of the scheme's run on nx elements."""
    times, us, vs, lams = solve(scheme, nx)
    return {
        "format": "signorini-external/2",
        "scene": "bar1d-dirichlet",
        "code": {"name": "verify_1d.py", "version": "1"},
        "label": SCHEMES[scheme][1],
        "scheme": scheme,
        "mass": "standard",
        "contact": "exact projection on the contact node",
        "mesh": {"nodes": [i * LENGTH / nx for i in range(nx + 1)]},
        "samples": [
            {"time": t, "displacement": u, "velocity": v, "lambda": lam}
            for t, u, v, lam in zip(times, us, vs, lams)
        ],
    }


def main(argv):
    if len(argv) < 3 or argv[1] not in SCHEMES:
        sys.exit("usage: verify_1d.py crank-nicolson|backward-euler OUT_DIR [NX ...]")
    scheme, out = argv[1], argv[2]
    levels = [int(a) for a in argv[3:]] or [10, 20, 40, 80]
    os.makedirs(out, exist_ok=True)
    for nx in levels:
        path = os.path.join(out, "nx%d.json" % nx)
        with open(path, "w") as f:
            json.dump(run_file(scheme, nx), f)
        print(path)


if __name__ == "__main__":
    main(sys.argv)
