//! Engine checks: the P1 assembly of §3.1–3.2, the exact Signorini–Dirichlet solution of §5.1
//! (eqs. 41–42 and the phase after the impact), the complementarity conditions (32d), (34d) and
//! (36) at every step of every scheme of Tables 1–2, second-order convergence of Crank–Nicolson
//! on a smooth solution, the gating of the observers, input validation and the time grid.
//!
//! Every expected value is computed here independently of the library (by hand formulas, finite
//! differences or our own quadrature), never read back from the code under test.

use std::collections::BTreeSet;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use approx::assert_abs_diff_eq;
use signorini::error::Error;
use signorini::exact::{ExactSolution, SignoriniDirichlet};
use signorini::fem::{Bar1d, EndCondition, MassVariant, SymmetricMatrix};
use signorini::model::Model;
use signorini::norms::Norm;
use signorini::run::{self, time_grid, Observables, Problem1d, RunConfig};
use signorini::schemes::{initial_state, integrator, PaoliSchatzman, Scheme, TimeIntegrator};
use signorini::studies::benchmark;

/// The Signorini–Dirichlet benchmark of `scenes/bar1d-dirichlet.json`, to `horizon`.
fn dirichlet(horizon: f64) -> Problem1d {
    benchmark::dirichlet(Path::new(env!("CARGO_MANIFEST_DIR")), horizon).unwrap()
}

/// The clamped bar vibrating in its first mode (no obstacle, a smooth solution) of
/// `scenes/bar1d-free.json`, to `horizon`.
fn free_vibration(horizon: f64) -> Problem1d {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (_, problem) = benchmark::bar_scene(root, "scenes/bar1d-free.json").unwrap();
    Problem1d { horizon, ..problem }
}

const END_CONDITIONS: [EndCondition; 2] = [EndCondition::Clamped, EndCondition::Free];
const MESHES: [usize; 4] = [1, 2, 7, 64];

/// The matrix as a dense array, read entry by entry through [`SymmetricMatrix::get`].
fn dense(a: &SymmetricMatrix) -> Vec<Vec<f64>> {
    let n = a.dim();
    (0..n)
        .map(|i| (0..n).map(|j| a.get(i, j)).collect())
        .collect()
}

/// `A x` from the dense entries.
fn dense_mul(a: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
    a.iter()
        .map(|row| row.iter().zip(x).map(|(aij, xj)| aij * xj).sum())
        .collect()
}

/// The row sums `(M·1)_i` of the consistent P1 mass matrix by hand: every element `e ∋ i`
/// contributes `ρh/6 · (2 + [the other node of e is a kept dof])` (§3.1, `φ_i` hat functions,
/// `∫ φ_i² = h/3`, `∫ φ_i φ_j = h/6` per element).
fn hand_mass_row_sums(nx: usize, n_dofs: usize, rho: f64, h: f64) -> Vec<f64> {
    (0..n_dofs)
        .map(|i| {
            let mut sum = 0.0;
            // Element i − 1 (nodes i − 1, i) and element i (nodes i, i + 1), when they exist.
            if i >= 1 {
                sum += rho * h / 6.0 * 3.0; // node i − 1 is always a kept dof
            }
            if i < nx {
                let other_kept = i + 1 < n_dofs;
                sum += rho * h / 6.0 * if other_kept { 3.0 } else { 2.0 };
            }
            sum
        })
        .collect()
}

/// §3.1: the consistent mass matrix `M_ij = ∫_0^L ρ φ_i φ_j` integrates the density: its entries
/// sum to `ρL` for the free bar (`V_h^Neu`, `Σ φ_i = 1`), and for the clamped bar (`V_h^Dir`,
/// node `m` eliminated) every row sum matches the hand computation, total `ρ(L − 2h/3)`.
#[test]
fn standard_mass_integrates_the_density() {
    for length in [1.0, 2.5] {
        for rho in [1.0, 3.0] {
            for nx in MESHES {
                for end in END_CONDITIONS {
                    let bar = Bar1d::new(length, nx, rho, 1.0, end).unwrap();
                    let h = length / nx as f64;
                    let m = bar.mass(MassVariant::Standard);
                    let n = bar.n_dofs();
                    assert_eq!(m.dim(), n);
                    assert_eq!(
                        n,
                        match end {
                            EndCondition::Clamped => nx,
                            EndCondition::Free => nx + 1,
                        }
                    );
                    let expected_total = match end {
                        EndCondition::Free => rho * length,
                        EndCondition::Clamped => rho * (length - 2.0 * h / 3.0),
                    };
                    let entries = dense(&m);
                    let total: f64 = entries.iter().flatten().sum();
                    assert_abs_diff_eq!(total, expected_total, epsilon = 1e-12 * length * rho);
                    assert_abs_diff_eq!(
                        m.sum_of_entries(),
                        expected_total,
                        epsilon = 1e-12 * length * rho
                    );

                    let ones = vec![1.0; n];
                    let hand = hand_mass_row_sums(nx, n, rho, h);
                    let from_entries = dense_mul(&entries, &ones);
                    let mut from_product = vec![f64::NAN; n];
                    m.mul_into(&ones, &mut from_product);
                    for i in 0..n {
                        assert_abs_diff_eq!(from_entries[i], hand[i], epsilon = 1e-14);
                        assert_abs_diff_eq!(from_product[i], hand[i], epsilon = 1e-14);
                    }
                    // The element matrix itself: ρh/3 on the diagonal of a boundary node, ρh/6
                    // off the diagonal.
                    assert_abs_diff_eq!(m.get(0, 0), rho * h / 3.0, epsilon = 1e-15);
                    if n > 1 {
                        assert_abs_diff_eq!(m.get(0, 1), rho * h / 6.0, epsilon = 1e-15);
                    }
                }
            }
        }
    }
}

/// §3.1: `S_ij = ∫ E φ_i' φ_j'`. With both ends free, constants are rigid motions: `S·1 = 0`;
/// the energy of `u = x` is `½ ∫ E u_x² = EL/2`, and `S x` is the boundary flux
/// `(−E, 0, …, 0, E)`. With the far end clamped `S` is positive definite: `1ᵀS1 = E/h`
/// (only the last element is strained).
#[test]
fn stiffness_annihilates_constants_on_the_free_bar() {
    for length in [1.0, 2.5] {
        for (rho, c) in [(1.0, 1.0), (2.0, 1.5)] {
            let young = rho * c * c;
            for nx in MESHES {
                let h = length / nx as f64;
                let free = Bar1d::new(length, nx, rho, c, EndCondition::Free).unwrap();
                let s = free.stiffness();
                let n = free.n_dofs();
                let ones = vec![1.0; n];
                let mut s1 = vec![f64::NAN; n];
                s.mul_into(&ones, &mut s1);
                let dense_s1 = dense_mul(&dense(&s), &ones);
                for i in 0..n {
                    assert!(s1[i].abs() <= 1e-12, "nx={nx}: (S·1)_{i} = {}", s1[i]);
                    assert!(dense_s1[i].abs() <= 1e-12, "nx={nx}: dense (S·1)_{i}");
                }
                let x = free.interpolate(|x| x);
                let mut sx = vec![f64::NAN; n];
                s.mul_into(&x, &mut sx);
                for (i, v) in sx.iter().enumerate() {
                    let expected = if i == 0 {
                        -young
                    } else if i == nx {
                        young
                    } else {
                        0.0
                    };
                    assert_abs_diff_eq!(*v, expected, epsilon = 1e-11 * young);
                }
                assert_abs_diff_eq!(
                    s.quadratic_form(&x),
                    young * length,
                    epsilon = 1e-11 * young * length
                );

                let clamped = Bar1d::new(length, nx, rho, c, EndCondition::Clamped).unwrap();
                let sc = clamped.stiffness();
                assert_abs_diff_eq!(
                    sc.quadratic_form(&vec![1.0; nx]),
                    young / h,
                    epsilon = 1e-12 * young / h
                );
            }
        }
    }
}

/// §3.2: `M^mod_ij = ∫_h^L φ_i φ_j`, i.e. `M^mod = [[0, 0], [0, M̄]]` — a zero row and column
/// at the contact dof; `M̄` equals `M` except at `(1, 1)`, which lacks element 0's `ρh/3`.
/// The model detects the massless dofs from the zero rows.
#[test]
fn redistributed_mass_drops_exactly_element_zero() {
    for rho in [1.0, 3.0] {
        for nx in MESHES {
            for end in END_CONDITIONS {
                let bar = Bar1d::new(1.0, nx, rho, 1.0, end).unwrap();
                let h = bar.h();
                let n = bar.n_dofs();
                let standard = bar.mass(MassVariant::Standard);
                let modified = bar.mass(MassVariant::Redistributed);
                assert_eq!(modified.dim(), n);
                // Element 0's diagonal contribution as the element matrix ρh/6·[[2,1],[1,2]]
                // holds it (equal to ρh/3 up to one rounding).
                let element_diagonal = 2.0 * (rho * h / 6.0);
                assert_abs_diff_eq!(element_diagonal, rho * h / 3.0, epsilon = 1e-16);
                for i in 0..n {
                    for j in 0..n {
                        let got = modified.get(i, j);
                        let expected = if i == 0 || j == 0 {
                            0.0
                        } else if i == 1 && j == 1 {
                            standard.get(1, 1) - element_diagonal
                        } else {
                            standard.get(i, j)
                        };
                        assert_eq!(
                            got, expected,
                            "nx={nx} {end:?} ρ={rho}: M^mod({i},{j}) = {got}, expected {expected}"
                        );
                    }
                }
                if n > 1 && nx > 1 {
                    // Node 1 is interior: its remaining mass is element 1's ρh/3.
                    assert_abs_diff_eq!(modified.get(1, 1), rho * h / 3.0, epsilon = 1e-15);
                }
                // Element 0's entries on kept dofs: all four (ρh in total), or only (0, 0) when
                // node 1 is the eliminated clamped end.
                let removed = if n > 1 { rho * h } else { rho * h / 3.0 };
                assert_abs_diff_eq!(
                    modified.sum_of_entries(),
                    standard.sum_of_entries() - removed,
                    epsilon = 1e-12
                );

                let model = Model::bar1d(&bar, MassVariant::Redistributed, Some(0.0), None);
                // Nodes touched only by element 0 carry no mass: node 0 always, node 1 too when
                // the mesh is a single free element.
                let expected_massless: Vec<usize> = if nx == 1 && end == EndCondition::Free {
                    vec![0, 1]
                } else {
                    vec![0]
                };
                assert_eq!(model.massless_dofs(), expected_massless.as_slice());
                if nx > 1 {
                    assert_eq!(model.massless_dofs(), &[0]);
                    assert!(model.contact_is_massless());
                }
                let std_model = Model::bar1d(&bar, MassVariant::Standard, Some(0.0), None);
                assert!(std_model.massless_dofs().is_empty());
                assert!(!std_model.contact_is_massless());
            }
        }
    }
}

/// §3.1–3.2: `M`, `M^mod` and `S` are Gram matrices of the hat functions, hence symmetric (both
/// triangles are stored; they must agree exactly).
#[test]
fn mass_and_stiffness_are_symmetric() {
    for nx in MESHES {
        for end in END_CONDITIONS {
            let bar = Bar1d::new(1.3, nx, 2.0, 0.7, end).unwrap();
            for (what, a) in [
                ("M", bar.mass(MassVariant::Standard)),
                ("M^mod", bar.mass(MassVariant::Redistributed)),
                ("S", bar.stiffness()),
            ] {
                let n = a.dim();
                let mut nonzero = 0;
                for i in 0..n {
                    for j in 0..n {
                        let (aij, aji) = (a.get(i, j), a.get(j, i));
                        assert_eq!(aij, aji, "{what} nx={nx} {end:?} at ({i},{j})");
                        if aij != 0.0 {
                            nonzero += 1;
                        }
                        if i.abs_diff(j) > 1 {
                            assert_eq!(aij, 0.0, "{what}: P1 matrices are tridiagonal");
                        }
                    }
                }
                if what != "M^mod" || nx > 1 {
                    assert!(nonzero > 0, "{what} nx={nx} {end:?} is empty");
                }
            }
        }
    }
}

/// §3.1: `h = L/m` needs `m ≥ 1` and `L > 0`; the density must be a positive number. Each
/// rejection names the offending parameter.
#[test]
fn bar_rejects_invalid_parameters_naming_them() {
    let cases: [(&str, f64, usize, f64, f64); 8] = [
        ("nx", 1.0, 0, 1.0, 1.0),
        ("length", 0.0, 4, 1.0, 1.0),
        ("length", -1.0, 4, 1.0, 1.0),
        ("length", f64::NAN, 4, 1.0, 1.0),
        ("density", 1.0, 4, f64::NAN, 1.0),
        ("density", 1.0, 4, -2.0, 1.0),
        ("density", 1.0, 4, 0.0, 1.0),
        ("wave_speed", 1.0, 4, 1.0, f64::INFINITY),
    ];
    for (name, length, nx, density, c) in cases {
        for end in END_CONDITIONS {
            let err = Bar1d::new(length, nx, density, c, end).expect_err(name);
            assert_eq!(err.name, name, "{length} {nx} {density} {c}");
            assert!(err.to_string().contains(name), "{err}");
        }
    }
    assert!(Bar1d::new(1.0, 1, 1.0, 1.0, EndCondition::Free).is_ok());
}

// ---------------------------------------------------------------------------------------------
// The exact solution of §5.1.
// ---------------------------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------------
// Complementarity at every step.
// ---------------------------------------------------------------------------------------------

const COMPLEMENTARITY_TOL: f64 = 1e-12;

fn dirichlet_setup(nx: usize, mass: MassVariant) -> (Bar1d, Model, Vec<f64>, Vec<f64>) {
    let bar = Bar1d::unit(nx, EndCondition::Clamped).unwrap();
    let model = Model::bar1d(&bar, mass, Some(0.0), None);
    let exact = SignoriniDirichlet;
    let u0 = bar.interpolate(|x| exact.eval(x, 0.0).u);
    let v0 = bar.interpolate(|x| exact.eval(x, 0.0).ut);
    (bar, model, u0, v0)
}

fn check_complementarity(what: &str, step: usize, gap: f64, lambda: f64) {
    assert!(
        gap >= -COMPLEMENTARITY_TOL,
        "{what} step {step}: gap {gap:e} < 0"
    );
    assert!(
        lambda <= COMPLEMENTARITY_TOL,
        "{what} step {step}: λ = {lambda:e} > 0"
    );
    assert!(
        (gap * lambda).abs() <= COMPLEMENTARITY_TOL,
        "{what} step {step}: gap·λ = {:e}",
        gap * lambda
    );
}

/// Eqs. (32d) and (34d): `0 ≤ u_0^{n+1} ⟂ λ^{n+1} ≤ 0` at every step; eq. (36):
/// `0 ≤ (u_0^{n+1} + e u_0^{n−1})/(1 + e) ⟂ λ^n ≤ 0` (the start step is one Newmark(β, ½)
/// step, constrained at `t_1`). Every scheme of Tables 1–2, both mass matrices, §5.2 setting.
#[test]
fn complementarity_holds_at_every_step() {
    const NX: usize = 40;
    const RATIO: f64 = 10.0;
    const HORIZON: f64 = 3.0;
    for scheme in Scheme::paper_schemes() {
        for mass in MassVariant::ALL {
            let (bar, model, u0, v0) = dirichlet_setup(NX, mass);
            let (steps, dt) = time_grid(HORIZON, bar.h(), RATIO);
            assert_eq!(steps, 1200);
            let what = format!("{scheme} {mass}");
            let mut contact_steps = 0;
            match scheme {
                Scheme::PaoliSchatzman { beta, restitution } => {
                    let start = initial_state(&model, &u0, &v0).unwrap();
                    let mut s = PaoliSchatzman::new(&model, beta, restitution, dt, start).unwrap();
                    for step in 1..=steps {
                        let u_older = s.previous_displacement()[0];
                        let u_old = s.displacement()[0];
                        s.advance().unwrap();
                        assert_eq!(s.previous_displacement()[0], u_old);
                        let u_new = s.displacement()[0];
                        let constrained = if step == 1 {
                            u_new
                        } else {
                            (u_new + restitution * u_older) / (1.0 + restitution)
                        };
                        let lambda = s.scheme_multiplier()[0];
                        check_complementarity(&what, step, constrained, lambda);
                        if lambda < 0.0 {
                            contact_steps += 1;
                        }
                    }
                }
                _ => {
                    let mut s = integrator(&model, scheme, dt, &u0, &v0).unwrap();
                    for step in 1..=steps {
                        s.advance().unwrap();
                        assert_eq!(s.step_index(), step);
                        let gap = s.displacement()[0];
                        let lambda = s.multiplier().value[0];
                        check_complementarity(&what, step, gap, lambda);
                        if lambda < 0.0 {
                            contact_steps += 1;
                        }
                    }
                }
            }
            assert!(
                contact_steps > 0,
                "{what}: the run never touches the obstacle"
            );
            if mass == MassVariant::Redistributed {
                // With M^mod the contact node does not chatter (§4.2, §5.2): it stays in
                // contact through nearly all of the exact contact phase t ∈ (1, 2), ~400 steps.
                let exact_phase_steps = (1.0 / dt).round() as usize;
                assert!(
                    contact_steps >= exact_phase_steps * 9 / 10,
                    "{what}: only {contact_steps} contact steps, exact phase {exact_phase_steps}"
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Convergence on a smooth solution.
// ---------------------------------------------------------------------------------------------

fn only(norms: &[Norm]) -> Observables {
    Observables {
        norms: norms.iter().copied().collect(),
        ..Observables::default()
    }
}

/// The least-squares slope of `log e` against `log h`.
fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    let xs: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let ys: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

fn smooth_errors(mass: MassVariant) -> (Vec<f64>, Vec<f64>) {
    let problem = free_vibration(4.0);
    let mut hs = Vec::new();
    let mut errors = Vec::new();
    for nx in [10, 20, 40, 80] {
        let config = RunConfig {
            nx,
            ratio: 1.0,
            scheme: Scheme::CRANK_NICOLSON,
            mass,
            observables: only(&[Norm::DisplacementLinfH]),
        };
        let result = run::run(&problem, &config).unwrap();
        assert_eq!(result.errors.len(), 1);
        hs.push(result.h);
        errors.push(result.errors[&Norm::DisplacementLinfH]);
    }
    (hs, errors)
}

#[test]
fn fitted_rate_recovers_a_known_power() {
    let h = [0.1, 0.05, 0.025];
    let e: Vec<f64> = h.iter().map(|x: &f64| 3.0 * x.powf(1.5)).collect();
    assert_abs_diff_eq!(fitted_rate(&h, &e), 1.5, epsilon = 1e-12);
}

/// §3.2: Crank–Nicolson (Newmark ¼, ½, eq. 32) is second-order consistent and the P1 mass
/// matrix is second order in `L∞(0, T; L²)`: on the smooth first mode (no obstacle), with
/// `Δx/Δt = 1` as in §4.2, the error falls by 4 per halving of `h`.
#[test]
fn crank_nicolson_converges_at_second_order_on_a_smooth_solution() {
    let (hs, errors) = smooth_errors(MassVariant::Standard);
    let rate = fitted_rate(&hs, &errors);
    println!("standard mass, Crank–Nicolson, u_Linf_H: errors {errors:?}, rate {rate:.4}");
    assert!(
        (1.9..=2.1).contains(&rate),
        "fitted rate {rate}, errors {errors:?}"
    );
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (3.5..=4.5).contains(&ratio),
            "ratio {ratio}, errors {errors:?}"
        );
    }
}

/// §3.2: with `M^mod` the node at `x = 0` loses its inertia even without obstacle (element 0's
/// mass is removed, not moved); the paper recalls the method still converges ([DPP*12]).
#[test]
fn redistributed_mass_still_converges_on_a_smooth_solution() {
    let (hs, errors) = smooth_errors(MassVariant::Redistributed);
    let rate = fitted_rate(&hs, &errors);
    println!("redistributed mass, Crank–Nicolson, u_Linf_H: errors {errors:?}, rate {rate:.4}");
    for w in errors.windows(2) {
        assert!(w[1] < w[0], "errors must decrease: {errors:?}");
    }
    assert!(rate >= 1.0, "fitted rate {rate}, errors {errors:?}");
}

// ---------------------------------------------------------------------------------------------
// Observers, validation, time grid.
// ---------------------------------------------------------------------------------------------

/// Only the requested norms are evaluated (the Tables 1–2 columns are independent).
#[test]
fn space_norms_are_evaluated_only_when_requested() {
    let problem = dirichlet(1.5);
    let config = |norms: &[Norm]| RunConfig {
        nx: 10,
        ratio: 10.0,
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
        observables: only(norms),
    };
    let energy_only = run::run(&problem, &config(&[Norm::EnergyLinf, Norm::EnergyL2])).unwrap();
    assert_eq!(energy_only.space_norm_evaluations, 0);
    assert_eq!(
        energy_only.errors.keys().copied().collect::<Vec<_>>(),
        vec![Norm::EnergyLinf, Norm::EnergyL2]
    );
    assert_eq!(energy_only.steps, 150);

    let with_u = run::run(&problem, &config(&[Norm::DisplacementLinfH])).unwrap();
    assert_eq!(with_u.space_norm_evaluations, with_u.steps + 1);
    assert!(with_u.errors[&Norm::DisplacementLinfH] > 0.0);

    let free = free_vibration(1.0);
    let result = run::run(&free, &config(&[Norm::MultiplierL2]));
    match result {
        Err(Error::Parameter(p)) => assert_eq!(p.name, "norm"),
        other => panic!("lambda_L2 without obstacle must be rejected, got {other:?}"),
    }
}

/// Bad input through `run::run` is a `ParameterError` naming the parameter (the ranges of
/// eqs. 32, 34, 36: β > 0, γ ≥ 0, θ ∈ (0, 1], e ∈ [0, 1]), never a panic.
#[test]
fn run_rejects_bad_input_naming_the_parameter() {
    let base = RunConfig {
        nx: 8,
        ratio: 10.0,
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
        observables: only(&[Norm::DisplacementLinfH]),
    };
    let problem = dirichlet(0.5);
    assert!(run::run(&problem, &base).is_ok());

    let with = |f: &dyn Fn(&mut RunConfig)| {
        let mut c = base.clone();
        f(&mut c);
        c
    };
    let mut cases: Vec<(&str, Problem1d, RunConfig)> = vec![
        ("nx", problem.clone(), with(&|c| c.nx = 0)),
        ("ratio", problem.clone(), with(&|c| c.ratio = 0.0)),
        ("ratio", problem.clone(), with(&|c| c.ratio = -1.0)),
        ("ratio", problem.clone(), with(&|c| c.ratio = f64::NAN)),
        (
            "beta",
            problem.clone(),
            with(&|c| {
                c.scheme = Scheme::Newmark {
                    beta: -1.0,
                    gamma: 0.5,
                }
            }),
        ),
        (
            "theta",
            problem.clone(),
            with(&|c| c.scheme = Scheme::Theta { theta: 1.5 }),
        ),
        (
            "theta",
            problem.clone(),
            with(&|c| c.scheme = Scheme::Theta { theta: 0.0 }),
        ),
        (
            "e",
            problem.clone(),
            with(&|c| {
                c.scheme = Scheme::PaoliSchatzman {
                    beta: 0.25,
                    restitution: 2.0,
                }
            }),
        ),
        (
            "gamma",
            problem.clone(),
            with(&|c| {
                c.scheme = Scheme::Newmark {
                    beta: 0.25,
                    gamma: -0.1,
                }
            }),
        ),
    ];
    for horizon in [0.0, -1.0, f64::NAN] {
        let mut p = problem.clone();
        p.horizon = horizon;
        cases.push(("horizon", p, base.clone()));
    }
    for (name, problem, config) in cases {
        let outcome = catch_unwind(AssertUnwindSafe(|| run::run(&problem, &config)));
        let result = outcome.unwrap_or_else(|_| panic!("{name}: run panicked on {config:?}"));
        match result {
            Err(Error::Parameter(p)) => {
                assert_eq!(p.name, name, "{config:?}");
                let message = Error::Parameter(p).to_string();
                assert!(
                    message.contains(&format!("{name} = ")),
                    "message {message:?} does not name {name}"
                );
            }
            other => panic!("{name}: expected a parameter error, got {other:?}"),
        }
    }
}

/// The scheme and mass names of Tables 1–2 parse; unknown names are rejected with the list of
/// valid ones.
#[test]
fn scheme_and_mass_names_parse() {
    assert_eq!(
        "crank-nicolson".parse::<Scheme>().unwrap(),
        Scheme::CRANK_NICOLSON
    );
    assert_eq!(
        "newmark(beta=0.3,gamma=0.6)".parse::<Scheme>().unwrap(),
        Scheme::Newmark {
            beta: 0.3,
            gamma: 0.6
        }
    );
    let err = "bogus".parse::<Scheme>().unwrap_err();
    assert!(err.to_string().contains("crank-nicolson"), "{err}");
    assert!(err.to_string().contains("bogus"), "{err}");
    // Parsed parameters are validated too.
    let err = "theta(theta=1.5)".parse::<Scheme>().unwrap_err();
    assert_eq!(err.name, "theta");

    assert_eq!(
        "standard".parse::<MassVariant>().unwrap(),
        MassVariant::Standard
    );
    assert_eq!(
        "redistributed".parse::<MassVariant>().unwrap(),
        MassVariant::Redistributed
    );
    let err = "heavy".parse::<MassVariant>().unwrap_err();
    assert!(err.to_string().contains("heavy"), "{err}");
    assert!(err.to_string().contains("standard"), "{err}");
}

/// §5.2: `Δx/Δt = 10`; the grid lands exactly on the horizon.
#[test]
fn time_grid_lands_on_the_horizon() {
    let (steps, dt) = time_grid(3.0, 0.1, 10.0);
    assert_eq!(steps, 300);
    assert_abs_diff_eq!(dt * steps as f64, 3.0, epsilon = 1e-12);
    assert_abs_diff_eq!(dt, 0.01, epsilon = 1e-15);

    // A nominal step that does not divide the horizon: round the step count up, so that
    // Δt never exceeds h / ratio.
    let (steps, dt) = time_grid(1.0, 0.3, 1.0);
    assert_eq!(steps, 4);
    assert_abs_diff_eq!(dt, 0.25, epsilon = 1e-15);
    for (horizon, h, ratio) in [
        (3.0, 1.0 / 40.0, 10.0),
        (4.0, 0.0125, 1.0),
        (6.0, 0.05, 10.0),
    ] {
        let (steps, dt) = time_grid(horizon, h, ratio);
        assert_eq!(steps, (horizon * ratio / h).round() as usize);
        assert_abs_diff_eq!(dt * steps as f64, horizon, epsilon = 1e-12);
        assert!(dt <= h / ratio * (1.0 + 1e-12));
    }
}
