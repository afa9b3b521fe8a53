//! The exact solution of the gravity benchmark (1D paper §4): free fall, Signorini and Neumann
//! conditions, the wave equation with the load `f = −g`, agreement with the paper's series
//! (eqs. 39–40), the impact times, energy conservation, and the quadrature the harness uses.

use signorini::engine::exact::{BouncingBar, ExactSolution, Pointwise};
use signorini::harness::run::norms::gauss_legendre;
use std::f64::consts::PI;

/// The paper's (§4.2) and other parameter sets `(L, g, u⁰)`: `t₁ = 3L` exactly (the paper's
/// impact times hold), a heavy bar (`V < 2gL`: contacts longer than `2L`, force crossing 0),
/// and a set whose contacts split into several intervals.
const PAPER: (f64, f64, f64) = (1.0, 0.11, 0.5);
const T1_IS_3L: (f64, f64, f64) = (1.0, 0.125, 0.5625);
const HEAVY: (f64, f64, f64) = (1.0, 1.0, 0.25);
const SPLITTING: (f64, f64, f64) = (1.0, 0.2, 0.5);
const LONG_BAR: (f64, f64, f64) = (2.0, 0.3, 0.1);

fn bar((l, g, u0): (f64, f64, f64)) -> BouncingBar {
    BouncingBar::new(l, g, u0).expect("valid parameters")
}

/// `n` times spread over `[0, horizon)` by the golden ratio (no lattice to land on kinks).
fn sample_times(horizon: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..n).map(move |k| horizon * ((0.5 + k as f64) * 0.618_033_988_749_894_8).fract())
}

/// Eq. (39): `h₁(x, s) = −c min(x, L − |s − L|) + Σ_{n ≤ N} 2g/(Lν³)(cos νs − 1) sin νx`,
/// `ν = (n − ½)π/L`, with `c` the coefficient of the `min` term.
fn eq39(l: f64, g: f64, c: f64, x: f64, s: f64, terms: usize) -> f64 {
    let series: f64 = (1..=terms)
        .map(|n| {
            let nu = (n as f64 - 0.5) * PI / l;
            2.0 * g / (l * nu.powi(3)) * ((nu * s).cos() - 1.0) * (nu * x).sin()
        })
        .sum();
    -c * x.min(l - (s - l).abs()) + series
}

/// Eq. (40): `h₂(x, s) = u⁰ − g(s − t₁)²/2 − 2gL²/3 + Σ_{n ≤ N} 4g/λ² cos λs cos λx`,
/// `λ = nπ/L`.
fn eq40(l: f64, g: f64, u0: f64, x: f64, s: f64, terms: usize) -> f64 {
    let t1 = (2.0 * u0 / g).sqrt();
    let series: f64 = (1..=terms)
        .map(|n| {
            let lam = n as f64 * PI / l;
            4.0 * g / (lam * lam) * (lam * s).cos() * (lam * x).cos()
        })
        .sum();
    u0 - 0.5 * g * (s - t1).powi(2) - 2.0 * g * l * l / 3.0 + series
}

/// Bound on the tail `n > N` of eq. (39): `Σ 2g/(Lν³)·2 ≤ 2gL²/(π³(N − ½)²)`.
fn eq39_tail(l: f64, g: f64, terms: usize) -> f64 {
    2.0 * g * l * l / (PI.powi(3) * (terms as f64 - 0.5).powi(2))
}

/// Bound on the tail `n > N` of eq. (40): `Σ 4gL²/(π²n²) ≤ 4gL²/(π²N)`.
fn eq40_tail(l: f64, g: f64, terms: usize) -> f64 {
    4.0 * g * l * l / (PI * PI * terms as f64)
}

/// The pieces `[a, b]` of `[0, L]` between the breakpoints at `t`.
fn pieces(bar: &BouncingBar, t: f64) -> Vec<(f64, f64)> {
    let mut nodes = vec![0.0];
    bar.breakpoints(t, &mut nodes);
    nodes.push(bar.length());
    nodes.windows(2).map(|w| (w[0], w[1])).collect()
}

/// `∫₀^L F(u, u_x, u_t) dx` with `points` Gauss points on every piece between breakpoints
/// (and between the nodes of a uniform mesh of `nx` elements, if `nx > 0`).
fn integrate(
    bar: &BouncingBar,
    t: f64,
    points: usize,
    nx: usize,
    f: impl Fn(f64, Pointwise) -> f64,
) -> f64 {
    let (nodes, weights) = gauss_legendre(points);
    let mut cuts = vec![0.0, bar.length()];
    bar.breakpoints(t, &mut cuts);
    cuts.extend((1..nx).map(|k| bar.length() * k as f64 / nx as f64));
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut sum = 0.0;
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        for (&xi, &wi) in nodes.iter().zip(weights) {
            let x = 0.5 * (a + b) + 0.5 * (b - a) * xi;
            sum += 0.5 * (b - a) * wi * f(x, bar.eval(x, t));
        }
    }
    sum
}

/// `E(t) = ½∫(u_t² + u_x²) dx + ∫ g u dx`, exact on each piece (3 Gauss points, quadratic u).
fn energy_by_quadrature(bar: &BouncingBar, t: f64) -> f64 {
    let g = bar.gravity();
    integrate(bar, t, 3, 0, |_, p| {
        0.5 * (p.ut * p.ut + p.ux * p.ux) + g * p.u
    })
}

#[test]
fn free_fall_before_the_first_impact() {
    for params in [PAPER, HEAVY, LONG_BAR] {
        let bar = bar(params);
        let (l, g, u0) = params;
        let t1 = (2.0 * u0 / g).sqrt();
        assert!((bar.first_impact_time() - t1).abs() < 1e-15);
        assert!((bar.impact_speed() - (2.0 * u0 * g).sqrt()).abs() < 1e-15);
        assert!(
            (bar.impact_times()[0] - t1).abs() < 1e-14,
            "first contact begins at t₁"
        );
        for k in 0..200 {
            let t = t1 * k as f64 / 200.0;
            for i in 0..=20 {
                let x = l * i as f64 / 20.0;
                let p = bar.eval(x, t);
                assert!(
                    (p.u - (u0 - 0.5 * g * t * t)).abs() < 1e-14,
                    "u at ({x}, {t})"
                );
                assert!((p.ut + g * t).abs() < 1e-14, "u_t at ({x}, {t})");
                assert!(p.ux.abs() < 1e-14, "u_x at ({x}, {t})");
            }
            assert_eq!(bar.contact_multiplier(t), 0.0);
        }
        let mut kinks = Vec::new();
        bar.breakpoints(0.5 * t1, &mut kinks);
        assert!(kinks.is_empty(), "the falling bar is smooth");
    }
}

#[test]
fn first_contact_lasts_2l_with_the_force_of_the_derivation() {
    let bar = bar(PAPER);
    let (l, g, _) = PAPER;
    let (t1, v) = (bar.first_impact_time(), bar.impact_speed());
    let (begin, end) = bar.contact_intervals(20.0)[0];
    assert!((begin - t1).abs() < 1e-14);
    assert!(
        (end - (t1 + 2.0 * l)).abs() < 1e-12,
        "take-off at t₁ + 2L: {end}"
    );
    // λ(t) = −V − g(t − t₁) in the first contact, 0 just after.
    for k in 0..100 {
        let t = begin + 2.0 * l * k as f64 / 100.0;
        let expected = -v - g * (t - t1);
        assert!(
            (bar.contact_multiplier(t) - expected).abs() < 1e-13,
            "λ({t})"
        );
    }
    assert_eq!(bar.contact_multiplier(end + 1e-9), 0.0);
    // The state at take-off: u = g(x² − 2Lx), u_t = V.
    for i in 1..=20 {
        let x = l * i as f64 / 20.0;
        let p = bar.eval(x, end - 1e-12);
        assert!(
            (p.u - g * (x * x - 2.0 * l * x)).abs() < 1e-11,
            "u at take-off"
        );
        let p = bar.eval(x, end);
        assert!((p.ut - v).abs() < 1e-12, "u_t at take-off");
    }
}

#[test]
fn continuity_across_every_phase_change_and_every_kink() {
    let eta = 1e-9;
    for params in [PAPER, HEAVY, SPLITTING] {
        let bar = bar(params);
        let l = params.0;
        let horizon = bar.horizon().min(60.0);
        let mut events = Vec::new();
        for (begin, end) in bar.contact_intervals(horizon) {
            events.push(begin);
            if end < horizon {
                events.push(end);
            }
        }
        assert!(events.len() >= 6, "several phase changes: {events:?}");
        for &te in &events {
            for i in 0..=40 {
                let x = l * i as f64 / 40.0;
                let (a, b) = (bar.eval(x, te - eta), bar.eval(x, te + eta));
                assert!(
                    (a.u - b.u).abs() < 1e-8,
                    "u jumps at t = {te}, x = {x}: {} vs {}",
                    a.u,
                    b.u
                );
            }
        }
        for t in sample_times(horizon, 300) {
            let mut kinks = Vec::new();
            bar.breakpoints(t, &mut kinks);
            for &xk in &kinks {
                let (a, b) = (bar.eval(xk - eta, t), bar.eval(xk + eta, t));
                assert!((a.u - b.u).abs() < 1e-8, "u jumps at x = {xk}, t = {t}");
            }
        }
    }
}

#[test]
fn neumann_at_l_and_signorini_at_the_obstacle() {
    for params in [PAPER, T1_IS_3L, HEAVY, SPLITTING, LONG_BAR] {
        let bar = bar(params);
        let l = params.0;
        let (mut contact, mut flight) = (0, 0);
        for t in sample_times(bar.horizon(), 20_000) {
            let far = bar.eval(l, t);
            assert!(far.ux.abs() < 1e-12, "u_x(L, {t}) = {}", far.ux);
            let p = bar.eval(0.0, t);
            let lambda = bar.contact_multiplier(t);
            assert!(p.u >= -1e-13, "u(0, {t}) = {} < 0", p.u);
            assert!(lambda <= 0.0, "λ({t}) = {lambda} > 0");
            assert!((p.u * lambda).abs() < 1e-13, "u λ ≠ 0 at {t}");
            if bar.in_contact(t) {
                contact += 1;
                assert!(p.u.abs() < 1e-13, "u(0, {t}) = {} in contact", p.u);
                assert!((p.ux - lambda).abs() < 1e-12, "λ ≠ u_x(0, {t})");
                assert!(p.ut.abs() < 1e-12, "the contact point moves at {t}");
            } else {
                flight += 1;
                assert!(p.ux.abs() < 1e-12, "u_x(0, {t}) = {} in flight", p.ux);
            }
        }
        assert!(
            contact > 1000 && flight > 1000,
            "{params:?}: both phases sampled"
        );
    }
}

/// `u_tt − u_xx` and the first differences at `(x, t)` by central differences of step `d`.
fn differences(bar: &BouncingBar, x: f64, t: f64, d: f64) -> (f64, f64, f64) {
    let u = |x: f64, t: f64| bar.eval(x, t).u;
    let c = u(x, t);
    let utt = (u(x, t + d) - 2.0 * c + u(x, t - d)) / (d * d);
    let uxx = (u(x + d, t) - 2.0 * c + u(x - d, t)) / (d * d);
    let ux = (u(x + d, t) - u(x - d, t)) / (2.0 * d);
    let ut = (u(x, t + d) - u(x, t - d)) / (2.0 * d);
    (utt - uxx, ux, ut)
}

#[test]
fn wave_equation_with_the_gravity_load_between_kinks() {
    let d = 1e-3;
    for params in [PAPER, HEAVY, SPLITTING] {
        let bar = bar(params);
        let (l, g, _) = params;
        let (mut checked, mut in_contact) = (0, 0);
        for (k, t) in sample_times(bar.horizon() - 2.0 * d, 4000).enumerate() {
            if t < 2.0 * d {
                continue;
            }
            let x = 2.0 * d + (l - 4.0 * d) * ((k as f64 + 0.5) * 0.754_877_666_246_692_7).fract();
            // Away from every characteristic through a break of A or B (the stencil stays in
            // one polynomial piece of u).
            let mut kinks = Vec::new();
            bar.breakpoints(t, &mut kinks);
            if kinks.iter().any(|&xk| (xk - x).abs() < 2.0 * d) {
                continue;
            }
            let (residual, ux, ut) = differences(&bar, x, t, d);
            let p = bar.eval(x, t);
            assert!(
                (residual + g).abs() < 1e-7,
                "u_tt − u_xx = {residual} ≠ −g at ({x}, {t})"
            );
            assert!((ux - p.ux).abs() < 1e-9, "u_x at ({x}, {t})");
            assert!((ut - p.ut).abs() < 1e-9, "u_t at ({x}, {t})");
            checked += 1;
            let lambda = bar.contact_multiplier(t);
            if lambda < -0.05 {
                // The printed load f = −(g + u_x(0, t)) is not what the solution satisfies.
                assert!((residual + g + lambda).abs() > 0.04);
                in_contact += 1;
            }
        }
        assert!(
            checked > 2000 && in_contact > 100,
            "{params:?}: {checked}, {in_contact}"
        );
    }
}

#[test]
fn agrees_with_the_papers_series_in_the_first_contact_and_flight() {
    // 1000 terms, as the paper. Tolerance: the bound on the tail plus rounding.
    let terms = 1000;
    let (l, g, u0) = PAPER;
    let bar = bar(PAPER);
    let (t1, v) = (bar.first_impact_time(), bar.impact_speed());
    let contacts = bar.contact_intervals(20.0);
    let (t2, t3) = (contacts[0].1, contacts[1].0);
    let tol39 = eq39_tail(l, g, terms) + 1e-12;
    let tol40 = eq40_tail(l, g, terms) + 1e-12;
    assert!(tol39 < 1e-8 && tol40 < 5e-5, "{tol39}, {tol40}");
    let (mut worst39, mut worst40) = (0.0f64, 0.0f64);
    for k in 0..40 {
        let phase = (k as f64 + 0.5) / 40.0;
        for i in 0..=20 {
            let x = l * i as f64 / 20.0;
            let t = t1 + (t2 - t1) * phase;
            worst39 = worst39.max((bar.eval(x, t).u - eq39(l, g, v, x, t - t1, terms)).abs());
            let t = t2 + (t3 - t2) * phase;
            worst40 = worst40.max((bar.eval(x, t).u - eq40(l, g, u0, x, t - t2, terms)).abs());
        }
    }
    eprintln!("series vs closed form: eq. 39 {worst39:.2e} (tol {tol39:.2e}), eq. 40 {worst40:.2e} (tol {tol40:.2e})");
    assert!(worst39 < tol39, "eq. 39: {worst39}");
    assert!(worst40 < tol40, "eq. 40: {worst40}");
}

#[test]
fn printed_coefficient_of_eq_39_is_wrong() {
    // Eq. (39) prints −√(2u⁰/g) min(…): the bar ahead of the front would move at −t₁, not at
    // the impact velocity −√(2u⁰g).
    let (l, g, _) = PAPER;
    let bar = bar(PAPER);
    let (t1, v) = (bar.first_impact_time(), bar.impact_speed());
    let (x, s) = (0.7, 0.3);
    let printed = eq39(l, g, t1, x, s, 1000);
    let corrected = eq39(l, g, v, x, s, 1000);
    let exact = bar.eval(x, t1 + s).u;
    assert!((corrected - exact).abs() < 1e-8);
    assert!(
        (printed - exact).abs() > 0.5,
        "printed {printed} vs {exact}"
    );
    // With the printed coefficient u_t jumps at t₁: −t₁ after, −√(2u⁰g) before.
    let d = 1e-6;
    let ut_printed = (eq39(l, g, t1, x, d, 1000) - eq39(l, g, t1, x, 0.0, 1000)) / d;
    assert!((ut_printed + t1).abs() < 1e-3 && (bar.eval(x, t1 - d).ut + v).abs() < 1e-5);
}

#[test]
fn eq_38_holds_for_all_bounces_when_t1_is_3l() {
    // g = 2u⁰/(9L²): t₁ = 3L, and the paper's impact times 3L + 16kL, +2L, +8L, +10L are exact.
    let (l, g, u0) = T1_IS_3L;
    let bar = bar(T1_IS_3L);
    let t1 = bar.first_impact_time();
    assert_eq!(t1, 3.0 * l);
    let terms = 1000;
    let tol = eq39_tail(l, g, terms).max(eq40_tail(l, g, terms)) + 1e-12;
    let eq38 = |x: f64, t: f64| -> f64 {
        let v = bar.impact_speed();
        if t <= t1 {
            return u0 - 0.5 * g * t * t;
        }
        let k = ((t - t1) / (16.0 * l)).floor();
        let tk1 = 3.0 * l + 16.0 * k * l;
        let (tk2, tk3, tk4) = (tk1 + 2.0 * l, tk1 + 8.0 * l, tk1 + 10.0 * l);
        if t <= tk2 {
            eq39(l, g, v, x, t - tk1, terms)
        } else if t <= tk3 {
            eq40(l, g, u0, x, t - tk2, terms)
        } else if t <= tk4 {
            eq39(l, g, v, x, tk4 - t, terms)
        } else {
            u0 - 0.5 * g * (t - tk4 - t1).powi(2)
        }
    };
    let mut worst = 0.0f64;
    for t in sample_times(32.0 * l + t1, 300) {
        for i in 0..=10 {
            let x = l * i as f64 / 10.0;
            worst = worst.max((bar.eval(x, t).u - eq38(x, t)).abs());
        }
    }
    assert!(worst < tol, "eq. 38 vs closed form: {worst} (tol {tol})");
    let expected: Vec<f64> = (0..8)
        .map(|k| 3.0 * l + 8.0 * l * k as f64)
        .filter(|&t| t < bar.horizon())
        .collect();
    let impacts = bar.impact_times();
    assert_eq!(impacts.len(), expected.len());
    for (a, b) in impacts.iter().zip(&expected) {
        assert!((a - b).abs() < 1e-12, "impact {a} vs {b}");
    }
    for (begin, end) in bar.contact_intervals(bar.horizon()) {
        assert!((end - begin - 2.0 * l).abs() < 1e-12);
    }
    // Exactly periodic with period 16L.
    for t in sample_times(30.0, 200) {
        let (a, b) = (bar.eval(0.37, t), bar.eval(0.37, t + 16.0 * l));
        assert!((a.u - b.u).abs() < 1e-12 && (a.ut - b.ut).abs() < 1e-12);
    }
}

#[test]
fn impact_times_for_the_papers_g_are_not_the_papers() {
    // g = 0.11: t₁ = 3.0151134…, and the first flight ends at 11.0333379… (derivation:
    // y(s) = g[t₁s − s²/2 + σ(σ − 2L)] = 0), not at the paper's t₃ = 11.
    let bar = bar(PAPER);
    let impacts = bar.impact_times();
    let expected = [
        3.015_113_445_777_6,
        11.033_337_880_514_2,
        19.039_485_246_693_8,
    ];
    for (a, b) in impacts.iter().zip(expected) {
        assert!((a - b).abs() < 1e-11, "impact {a} vs {b}");
    }
    for (k, a) in impacts.iter().enumerate().take(6) {
        let paper = 3.0 + 8.0 * k as f64;
        assert!((a - paper).abs() > 0.01, "impact {k} at {a}, paper {paper}");
    }
    // The second impact from the closed form of the first flight.
    let (g, t1, t2) = (0.11, bar.first_impact_time(), bar.takeoff_times()[0]);
    let y = |s: f64| {
        let sigma = s.rem_euclid(2.0);
        g * (t1 * s - 0.5 * s * s + sigma * (sigma - 2.0))
    };
    let s3 = impacts[1] - t2;
    assert!(y(s3).abs() < 1e-12 && y(s3 - 1e-6) > 0.0);
}

#[test]
fn long_time_motion_tends_to_a_16l_periodic_one_without_reaching_it() {
    let bar = bar(PAPER).with_horizon(1100.0).expect("reachable");
    let contacts = bar.contact_intervals(bar.horizon());
    let bounces = ((bar.horizon() - 3.045_682_478_929) / 8.0).floor() as usize + 1;
    assert_eq!(contacts.len(), bounces, "one contact per bounce");
    for &(begin, end) in &contacts[..contacts.len() - 1] {
        assert!((end - begin - 2.0).abs() < 1e-9, "contact [{begin}, {end})");
    }
    // Flights last 6L + δ_k, δ_k > 0, shrinking by ≈ 0.205 every two bounces.
    let flights: Vec<f64> = contacts.windows(2).map(|w| w[1].0 - w[0].1 - 6.0).collect();
    for k in 0..16 {
        assert!(flights[k] > 0.0);
        let ratio = flights[k + 2] / flights[k];
        assert!((0.19..0.215).contains(&ratio), "δ ratio {ratio} at {k}");
    }
    // The state: far from periodic early, periodic to rounding late; period 16L, not 8L.
    let gap = |t0: f64, period: f64| {
        let mut worst = 0.0f64;
        for t in sample_times(16.0, 200) {
            for i in 0..=20 {
                let x = i as f64 / 20.0;
                worst = worst.max((bar.eval(x, t0 + t).u - bar.eval(x, t0 + t + period).u).abs());
            }
        }
        worst
    };
    assert!(gap(0.0, 16.0) > 1e-3);
    assert!(gap(100.0, 16.0) > 1e-8 && gap(100.0, 16.0) < 1e-5);
    assert!(gap(1000.0, 16.0) < 1e-11);
    assert!(gap(1000.0, 8.0) > 1e-2);
    let limit = contacts[contacts.len() - 2].0 - 8.0 * (contacts.len() - 2) as f64;
    assert!(
        (limit - 3.045_682_478_929).abs() < 1e-10,
        "impact phase {limit}"
    );
}

#[test]
fn energy_is_conserved_over_several_bounces() {
    for params in [PAPER, T1_IS_3L, HEAVY, SPLITTING, LONG_BAR] {
        let bar = bar(params);
        let (l, g, u0) = params;
        let e0 = g * u0 * l;
        assert_eq!(bar.energy(0.0), e0);
        assert!(bar.contact_intervals(bar.horizon()).len() >= 5);
        let mut drift = 0.0f64;
        for t in sample_times(bar.horizon(), 3000) {
            drift = drift.max((energy_by_quadrature(&bar, t) - e0).abs());
        }
        eprintln!(
            "{params:?}: energy {e0}, max drift {drift:.2e} to t = {}",
            bar.horizon()
        );
        assert!(drift < 1e-12 * e0.max(1.0), "{params:?}: drift {drift}");
        assert_eq!(bar.energy(bar.horizon()), e0);
    }
}

#[test]
fn energy_quadrature_needs_the_breakpoints() {
    // Without the kinks the same rule is off: the breakpoints list is complete and necessary.
    let bar = bar(PAPER);
    let g = bar.gravity();
    let t = 12.345;
    let mut kinks = Vec::new();
    bar.breakpoints(t, &mut kinks);
    assert!(!kinks.is_empty());
    let (nodes, weights) = gauss_legendre(3);
    let blind: f64 = (0..10)
        .flat_map(|e| nodes.iter().zip(weights).map(move |(xi, w)| (e, xi, w)))
        .map(|(e, xi, w)| {
            let x = (e as f64 + 0.5 + 0.5 * xi) / 10.0;
            let p = bar.eval(x, t);
            0.05 * w * (0.5 * (p.ut * p.ut + p.ux * p.ux) + g * p.u)
        })
        .sum();
    assert!((energy_by_quadrature(&bar, t) - bar.energy(t)).abs() < 1e-14);
    assert!((blind - bar.energy(t)).abs() > 1e-7, "{blind}");
}

#[test]
fn three_gauss_points_integrate_the_p1_error_exactly() {
    // The interpolation error of a P1 field, squared, on pieces between kinks and mesh nodes:
    // 3 points agree with 5 to rounding; 2 do not where u is curved (u_xx = g + A″ + B″ takes
    // the values 0, g and 2g, so u is affine on some pieces at some times).
    let bar = bar(PAPER);
    assert_eq!(bar.gauss_points(), 3);
    let nx = 7;
    let mut two_fails = 0;
    for t in [1.5, 4.2, 8.9, 13.7, 30.3] {
        let h = 1.0 / nx as f64;
        let nodal: Vec<f64> = (0..=nx).map(|k| bar.eval(k as f64 * h, t).u).collect();
        let interp = |x: f64| {
            let e = ((x / h) as usize).min(nx - 1);
            let s = (x - e as f64 * h) / h;
            nodal[e] * (1.0 - s) + nodal[e + 1] * s
        };
        let err2 = |x: f64, p: Pointwise| (interp(x) - p.u).powi(2);
        let (two, three, five) = (
            integrate(&bar, t, 2, nx, err2),
            integrate(&bar, t, 3, nx, err2),
            integrate(&bar, t, 5, nx, err2),
        );
        assert!(
            (three - five).abs() < 1e-13 * five + 1e-24,
            "t = {t}: {three} vs {five}"
        );
        if (two - five).abs() > 1e-4 * five {
            two_fails += 1;
        }
    }
    assert!(
        two_fails >= 3,
        "2 Gauss points are exact too often: {two_fails}"
    );
}

#[test]
fn breakpoints_are_sorted_inside_and_separate_quadratic_pieces() {
    for params in [PAPER, HEAVY, SPLITTING] {
        let bar = bar(params);
        let l = params.0;
        for t in sample_times(bar.horizon(), 200) {
            let mut kinks = vec![-1.0];
            bar.breakpoints(t, &mut kinks);
            assert_eq!(kinks[0], -1.0, "appends");
            assert!(kinks.windows(2).all(|w| w[0] < w[1]), "sorted at {t}");
            assert!(kinks[1..].iter().all(|&x| x > 0.0 && x < l));
            // On every piece u is a quadratic: its third difference vanishes.
            for (a, b) in pieces(&bar, t) {
                if b - a < 1e-6 {
                    continue;
                }
                let u = |s: f64| bar.eval(a + s * (b - a), t).u;
                let third = u(0.9) - 3.0 * u(0.63) + 3.0 * u(0.36) - u(0.09);
                assert!(
                    third.abs() < 1e-12,
                    "not quadratic on [{a}, {b}] at {t}: {third}"
                );
            }
        }
    }
}

#[test]
fn eval_many_agrees_with_eval_exactly() {
    for params in [PAPER, SPLITTING] {
        let bar = bar(params);
        let l = params.0;
        for t in sample_times(bar.horizon(), 50) {
            // The quadrature points of a mesh (sorted), then the same shuffled.
            let mut xs = Vec::new();
            let (nodes, _) = gauss_legendre(3);
            for (a, b) in pieces(&bar, t) {
                xs.extend(nodes.iter().map(|xi| 0.5 * (a + b) + 0.5 * (b - a) * xi));
            }
            xs.extend([0.0, l]);
            let n = xs.len();
            let shuffled: Vec<f64> = (0..n).map(|k| xs[(k * 7919) % n]).collect();
            xs.extend(shuffled);
            let mut out = vec![bar.eval(0.0, 0.0); xs.len()];
            bar.eval_many(t, &xs, &mut out);
            for (&x, o) in xs.iter().zip(&out) {
                assert_eq!(*o, bar.eval(x, t), "x = {x}, t = {t}");
            }
        }
    }
}

#[test]
fn bad_parameters_are_rejected_by_name() {
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let cases = [
            ("length", BouncingBar::new(bad, 0.11, 0.5)),
            ("gravity", BouncingBar::new(1.0, bad, 0.5)),
            ("initial_height", BouncingBar::new(1.0, 0.11, bad)),
        ];
        for (name, result) in cases {
            let err = result.expect_err("rejected");
            assert_eq!(err.name, name);
            assert!(err.to_string().contains(name), "{err}");
        }
        let err = BouncingBar::paper()
            .with_horizon(bad)
            .expect_err("rejected");
        assert_eq!(err.name, "horizon");
    }
    let paper = BouncingBar::paper();
    assert_eq!(
        (paper.length(), paper.gravity(), paper.initial_height()),
        (1.0, 0.11, 0.5)
    );
    assert_eq!(paper.name(), "bouncing-bar");
}

#[test]
#[should_panic(expected = "after its horizon")]
fn evaluating_after_the_horizon_panics() {
    let bar = BouncingBar::paper();
    bar.eval(0.5, bar.horizon() + 1.0);
}

#[test]
fn with_horizon_extends_without_changing_the_past() {
    let short = BouncingBar::paper();
    let long = BouncingBar::paper().with_horizon(200.0).expect("reachable");
    assert!(short.horizon() >= 16.0 * (short.first_impact_time() + 1.0));
    assert!(long.horizon() >= 200.0);
    for t in sample_times(short.horizon(), 300) {
        for x in [0.0, 0.3, 1.0] {
            assert_eq!(short.eval(x, t), long.eval(x, t));
        }
    }
}
