//! The exact Signorini–Dirichlet solution of §5.1 (eqs. 41–42 and the phase after the impact):
//! boundary and contact conditions, period 3, Lipschitz continuity, the wave equation zone by
//! zone and across the characteristics (d'Alembert's parallelogram rule), the initial data, the
//! energy 1/8 and the breakpoints.
//!
//! Every expected value is computed here independently of the library (by hand formulas, finite
//! differences or our own quadrature), never read back from the code under test.

use std::collections::BTreeSet;

use approx::assert_abs_diff_eq;
use signorini::engine::exact::{ExactSolution, SignoriniDirichlet};

/// `t mod 1` within the period, as the phases of §5.1 use it.
fn local_time(t: f64) -> f64 {
    t.rem_euclid(SignoriniDirichlet::PERIOD).fract()
}

fn grid(a: f64, b: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |k| a + (b - a) * k as f64 / n as f64)
}

/// §5.1, boundary conditions (3): clamped at `x = 1`; Signorini at `x = 0`:
/// `u(0, t) ≥ 0`, `λ(t) ≤ 0`, `u(0, t) λ(t) = 0`, `λ = u_x(0, ·)` while in contact
/// (`t mod 3 ∈ (1, 2)`, eq. 42), no contact force in the phases (41) and after the impact.
#[test]
fn signorini_dirichlet_boundary_conditions() {
    let exact = SignoriniDirichlet;
    let mut contact_samples = 0;
    let mut free_samples = 0;
    for t in grid(0.0, 9.0, 9 * 400 + 7) {
        assert_eq!(exact.eval(1.0, t).u, 0.0, "u(1, {t})");
        let u0 = exact.eval(0.0, t).u;
        let lambda = exact.contact_multiplier(t);
        assert!(u0 >= 0.0, "u(0, {t}) = {u0}");
        assert!(lambda <= 0.0, "λ({t}) = {lambda}");
        assert_eq!(u0 * lambda, 0.0, "complementarity at t = {t}");
        let tp = t.rem_euclid(3.0);
        if tp > 1.0 && tp < 2.0 {
            contact_samples += 1;
            assert_eq!(u0, 0.0, "in contact at {t}");
            assert_eq!(lambda, exact.eval(0.0, t).ux, "λ = u_x(0, t) at {t}");
            assert_eq!(lambda, -0.5, "eq. 42b: u_x = −½ in region II at t = {t}");
        } else if (tp > 0.0 && tp < 1.0) || tp > 2.0 {
            free_samples += 1;
            assert!(u0 > 0.0, "off contact at t = {t}: u(0) = {u0}");
            assert_eq!(lambda, 0.0, "no contact force at t = {t}");
        }
    }
    assert!(contact_samples > 1000 && free_samples > 2000);
}

/// §5.1: "the solution is periodic of period 3" (`u(·, 3) = u^0`, `u_t(·, 3) = v^0`).
#[test]
fn signorini_dirichlet_is_three_periodic() {
    let exact = SignoriniDirichlet;
    for x in grid(0.0, 1.0, 50) {
        for t in grid(0.0, 6.0, 6 * 50 + 3) {
            let a = exact.eval(x, t);
            for k in [1.0, 2.0, -1.0] {
                let b = exact.eval(x, t + 3.0 * k);
                assert_abs_diff_eq!(a.u, b.u, epsilon = 1e-12);
            }
            let b = exact.eval(x, t + 3.0);
            if (x - local_time(t)).abs() > 1e-9 && (x + local_time(t) - 1.0).abs() > 1e-9 {
                assert_eq!((a.ux, a.ut), (b.ux, b.ut), "derivatives at ({x}, {t})");
            }
        }
    }
}

/// §5.1: a continuous, piecewise affine solution whose slopes are `0` or `±½` — Lipschitz with
/// constant ½ in `x` and in `t`, across the characteristics and the phase changes `t = 1, 2, 3`.
#[test]
fn signorini_dirichlet_is_lipschitz_continuous() {
    let exact = SignoriniDirichlet;
    let (nx, nt) = (400, 1800);
    let dx = 1.0 / nx as f64;
    let dt = 6.0 / nt as f64;
    let mut largest_x_jump: f64 = 0.0;
    let mut largest_t_jump: f64 = 0.0;
    for i in 0..=nx {
        let x = i as f64 * dx;
        for k in 0..=nt {
            let t = k as f64 * dt;
            let u = exact.eval(x, t).u;
            if i < nx {
                let jump = (exact.eval(x + dx, t).u - u).abs();
                largest_x_jump = largest_x_jump.max(jump);
                assert!(jump <= 0.5 * dx + 1e-12, "x-jump {jump} at ({x}, {t})");
            }
            if k < nt {
                let jump = (exact.eval(x, t + dt).u - u).abs();
                largest_t_jump = largest_t_jump.max(jump);
                assert!(jump <= 0.5 * dt + 1e-12, "t-jump {jump} at ({x}, {t})");
            }
        }
    }
    // The solution is not constant: some increments reach the slope ½.
    assert!(largest_x_jump > 0.49 * dx && largest_t_jump > 0.49 * dt);
    // Across the phase boundaries, with tiny steps.
    for t in [1.0, 2.0, 3.0, 4.0] {
        for x in grid(0.0, 1.0, 20) {
            for eps in [1e-9, 1e-12] {
                let jump = (exact.eval(x, t + eps).u - exact.eval(x, t - eps).u).abs();
                assert!(jump <= eps + 1e-12, "jump {jump} across t = {t} at x = {x}");
            }
        }
    }
}

/// §5.1, eq. (1) with `f = 0`: inside every region of eqs. (41)–(42) and the phase after the
/// impact, the returned `u_x`, `u_t` are the derivatives of `u` and `u_tt − u_xx = 0`.
#[test]
fn signorini_dirichlet_solves_the_wave_equation_zone_by_zone() {
    let exact = SignoriniDirichlet;
    let fd = 1e-6;
    let fd2 = 1e-3;
    let margin = 5e-3;
    let mut checked = 0;
    let mut regions = BTreeSet::new();
    for x in grid(0.0, 1.0, 97) {
        for t in grid(0.0, 6.0, 6 * 97 + 5) {
            let tau = local_time(t);
            let near = |a: f64, b: f64| (a - b).abs() < margin;
            if near(x, 0.0)
                || near(x, 1.0)
                || near(x, tau)
                || near(x, 1.0 - tau)
                || near(tau, 0.0)
                || near(tau, 1.0)
            {
                continue;
            }
            checked += 1;
            let phase = t.rem_euclid(3.0).floor() as usize;
            regions.insert((phase, x < tau, x + tau > 1.0));
            let u = |x: f64, t: f64| exact.eval(x, t).u;
            let p = exact.eval(x, t);
            let ux = (u(x + fd, t) - u(x - fd, t)) / (2.0 * fd);
            let ut = (u(x, t + fd) - u(x, t - fd)) / (2.0 * fd);
            assert_abs_diff_eq!(p.ux, ux, epsilon = 1e-9);
            assert_abs_diff_eq!(p.ut, ut, epsilon = 1e-9);
            let uxx = (u(x + fd2, t) - 2.0 * p.u + u(x - fd2, t)) / (fd2 * fd2);
            let utt = (u(x, t + fd2) - 2.0 * p.u + u(x, t - fd2)) / (fd2 * fd2);
            assert!(
                (utt - uxx).abs() <= 1e-8,
                "u_tt − u_xx = {} at ({x}, {t})",
                utt - uxx
            );
            // Piecewise affine: each second derivative vanishes by itself.
            assert!(uxx.abs() <= 1e-8 && utt.abs() <= 1e-8);
            // The slopes of §5.1 are 0 or ±½.
            for d in [p.ux, p.ut] {
                assert!(d == 0.0 || d.abs() == 0.5, "slope {d} at ({x}, {t})");
            }
        }
    }
    assert!(checked > 20_000, "only {checked} interior samples");
    assert_eq!(regions.len(), 12, "all 3 phases × 4 regions sampled");
}

/// The wave equation holds across the characteristics too (in the weak sense): d'Alembert's
/// parallelogram rule `u(A) + u(C) = u(B) + u(D)` for every characteristic parallelogram inside
/// `[0, 1] × ℝ`, whatever the phase (§5.1 builds the solution by the characteristics method).
#[test]
fn signorini_dirichlet_satisfies_the_parallelogram_rule() {
    let exact = SignoriniDirichlet;
    let u = |x: f64, t: f64| exact.eval(x, t).u;
    let mut checked = 0;
    for x in grid(0.0, 1.0, 23) {
        for t in grid(0.0, 6.0, 131) {
            for a in [0.05, 0.17, 0.31] {
                for b in [0.04, 0.23, 0.4] {
                    // A = (x, t), B = A + a(1, 1), C = B + b(−1, 1), D = A + b(−1, 1).
                    if x + a > 1.0 || x - b < 0.0 {
                        continue;
                    }
                    let lhs = u(x, t) + u(x + a - b, t + a + b);
                    let rhs = u(x + a, t + a) + u(x - b, t + b);
                    assert_abs_diff_eq!(lhs, rhs, epsilon = 1e-12);
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 5_000);
}

/// §5.1: `u^0(x) = ½ − x/2`, `v^0 = 0` (so `u_x = −½` at `t = 0`).
#[test]
fn signorini_dirichlet_initial_data() {
    let exact = SignoriniDirichlet;
    for x in grid(0.0, 1.0, 1000) {
        let p = exact.eval(x, 0.0);
        assert_abs_diff_eq!(p.u, 0.5 - 0.5 * x, epsilon = 1e-15);
        assert_eq!(p.ut, 0.0);
        assert_eq!(p.ux, -0.5);
        // And again one and two periods later.
        for k in [1.0, 2.0] {
            assert_abs_diff_eq!(exact.eval(x, 3.0 * k).u, 0.5 - 0.5 * x, epsilon = 1e-12);
            assert_eq!(exact.eval(x, 3.0 * k).ut, 0.0);
        }
    }
}

/// §5.1: the energy `½ ∫_0^1 (u_t² + u_x²) dx` is `1/8` at all times (by our own midpoint rule).
#[test]
fn signorini_dirichlet_energy_is_one_eighth() {
    let exact = SignoriniDirichlet;
    let n = 20_000;
    let dx = 1.0 / n as f64;
    for t in [
        0.0, 0.1, 0.37, 0.5, 0.99, 1.0, 1.25, 1.5, 1.8, 2.0, 2.3, 2.75, 3.4, 5.9,
    ] {
        let energy: f64 = (0..n)
            .map(|i| {
                let p = exact.eval((i as f64 + 0.5) * dx, t);
                0.5 * (p.ut * p.ut + p.ux * p.ux) * dx
            })
            .sum();
        assert_abs_diff_eq!(energy, 0.125, epsilon = 1e-12);
        assert_eq!(exact.energy(t), 0.125);
    }
}

/// §5.1, Figure 6: the kinks of `u(·, t)` are the characteristics `x = τ`, `x = 1 − τ`,
/// `τ = t mod 1`; `breakpoints` lists them sorted, inside `(0, 1)`, without duplicates.
#[test]
fn signorini_dirichlet_breakpoints_are_the_characteristics() {
    let exact = SignoriniDirichlet;
    for t in grid(0.0, 6.0, 6 * 64 + 1).chain([0.5, 1.5, 2.5, 3.0, 1.0, 2.0]) {
        let mut out = Vec::new();
        exact.breakpoints(t, &mut out);
        let tau = local_time(t);
        assert!(
            out.windows(2).all(|w| w[0] < w[1]),
            "unsorted {out:?} at {t}"
        );
        assert!(out.iter().all(|&p| p > 0.0 && p < 1.0), "{out:?} at {t}");
        for p in [tau, 1.0 - tau] {
            if p > 0.0 && p < 1.0 {
                assert!(
                    out.iter().any(|&q| (q - p).abs() <= 1e-15),
                    "{p} missing from {out:?} at t = {t}"
                );
            }
        }
        let expected_len = if tau == 0.0 {
            0
        } else if tau == 0.5 {
            1
        } else {
            2
        };
        assert_eq!(out.len(), expected_len, "{out:?} at t = {t}");
        // u(·, t) is affine between consecutive breakpoints: check the midpoint of each piece.
        let mut pieces = vec![0.0];
        pieces.extend(&out);
        pieces.push(1.0);
        for w in pieces.windows(2) {
            let (a, b) = (w[0] + 1e-9, w[1] - 1e-9);
            let mid = exact.eval(0.5 * (a + b), t).u;
            let chord = 0.5 * (exact.eval(a, t).u + exact.eval(b, t).u);
            assert_abs_diff_eq!(mid, chord, epsilon = 1e-12);
        }
    }
}
