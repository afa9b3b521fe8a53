//! The local Delassus operator (issue 19, item 2): on a slab that covers the whole system it is
//! today's full operator; on 2D/3D box runs with the CG step solver, where the adaptive slab is
//! a strict part of the system, it reproduces the full operator's histories to 1e-8 of each
//! history's scale with complementarity at 1e-10, and a one-layer slab does not.

use std::path::Path;

use signorini::engine::contact::{
    ContactOperator, ContactTreatment, Delassus, LocalDelassus, SlabSolve,
};
use signorini::engine::fem::{MassVariant, SymmetricMatrix};
use signorini::engine::linalg::{LinearSolver, StepSolver, StepSolverKind};
use signorini::engine::problem::{Problem, Settings};
use signorini::engine::schemes::Scheme;
use signorini::harness::run::elastic::BoxProblem;
use signorini::harness::run::{run, BoxRun, Observables, RunConfig, RunStatus};
use signorini::harness::study::scene::Scene;

fn box_problem(scene: &str, contact: ContactTreatment) -> BoxProblem {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(scene);
    let Problem::Box(problem) = Scene::load(&path).unwrap().problem() else {
        panic!("{scene} is not a box scene")
    };
    BoxProblem { contact, ..problem }
}

/// The default settings with the step solver `linear_solver` and the contact operator
/// `operator`.
fn solved_by(linear_solver: LinearSolver, operator: ContactOperator) -> Settings {
    Settings {
        linear_solver,
        contact_operator: operator,
        ..Settings::default()
    }
}

/// The step matrix `M/(bΔt²) + S` of `scene` at level `nx` with `Δt = h/2`, and the
/// constraint rows of `contact`.
fn step_matrix(
    scene: &str,
    nx: usize,
    b: f64,
    contact: ContactTreatment,
) -> (
    SymmetricMatrix,
    Vec<signorini::engine::contact::ConstraintRow>,
) {
    step_matrix_with(scene, nx, b, contact, MassVariant::Standard)
}

/// [`step_matrix`] with the mass `mass`.
fn step_matrix_with(
    scene: &str,
    nx: usize,
    b: f64,
    contact: ContactTreatment,
    mass: MassVariant,
) -> (
    SymmetricMatrix,
    Vec<signorini::engine::contact::ConstraintRow>,
) {
    let problem = box_problem(scene, contact);
    let d = problem
        .discretise(
            nx,
            mass,
            &solved_by(LinearSolver::Cg, ContactOperator::Auto),
        )
        .unwrap();
    let dt = problem.lengths.last().unwrap() / nx as f64 / 2.0;
    let model = &d.model;
    let k = model
        .mass()
        .linear_combination(1.0 / (b * dt * dt), model.stiffness(), 1.0);
    let rows = model.contact_law().rows(model.contact().unwrap());
    (k, rows)
}

#[test]
fn a_slab_covering_the_system_is_the_full_operator() {
    let penalty = ContactTreatment::Penalty { gamma0: 10.0 };
    for (scene, nx) in [("scenes/bar2d.json", 20), ("scenes/bar3d.json", 10)] {
        for contact in [ContactTreatment::Multiplier, penalty] {
            let (k, rows) = step_matrix(scene, nx, 0.25, contact);
            let n = k.dim();
            let direct = StepSolver::new(k.clone(), StepSolverKind::Direct, "step").unwrap();
            let full = Delassus::new(&direct, n, &rows).unwrap();
            let mut local = LocalDelassus::new(&k, &rows, Some(usize::MAX)).unwrap();
            let slab = local.truncation();
            assert!(slab.whole, "{scene}: {slab:?}");
            assert_eq!(slab.slab_dofs, n, "{scene}");
            assert_eq!(
                local.matrix(),
                full.matrix(),
                "{scene} {contact}: W differs"
            );
            let mu: Vec<f64> = (0..rows.len()).map(|j| 1.0 + j as f64).collect();
            let (mut u_full, mut u_local) = (vec![0.5; n], vec![0.5; n]);
            full.apply_correction(&mu, &mut u_full);
            local.apply_correction(&mu, &mut u_local).unwrap();
            let scale = u_full.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            for (a, b) in u_local.iter().zip(&u_full) {
                assert!((a - b).abs() <= 1e-14 * scale, "{scene}: {a:e} vs {b:e}");
            }
        }
    }
}

/// The slab solved by CG on the cut box (what the local operator takes from
/// `CG_SLAB_FROM_DOFS` slab unknowns, 3D level 640's 279 k) has the factor's operator: the same
/// layers (the truncation ratio agrees to round-off), `W` to 1e-12 of its largest entry and the correction to 1e-12 of its scale, in 2D
/// and 3D, both masses (`M^mod` through the condensed-plane preconditioner), multiplier and
/// penalty.
#[test]
fn a_slab_solved_by_cg_has_the_factors_operator() {
    let penalty = ContactTreatment::Penalty { gamma0: 10.0 };
    for (scene, nx) in [("scenes/bar2d.json", 40), ("scenes/bar3d.json", 20)] {
        for mass in [MassVariant::Standard, MassVariant::Redistributed] {
            for contact in [ContactTreatment::Multiplier, penalty] {
                let (k, rows) = step_matrix_with(scene, nx, 0.25, contact, mass);
                let build = |choice| LocalDelassus::with_slab_solve(&k, &rows, None, choice);
                let (mut factor, mut cg) = (
                    build(SlabSolve::Factor).unwrap(),
                    build(SlabSolve::Cg).unwrap(),
                );
                let what = format!("{scene} {mass:?} {contact}");
                let (a, b) = (factor.truncation(), cg.truncation());
                assert_eq!((a.layers, a.slab_dofs), (b.layers, b.slab_dofs), "{what}");
                let largest = factor.matrix().iter().fold(0.0_f64, |m, w| m.max(w.abs()));
                for (a, b) in cg.matrix().iter().zip(factor.matrix()) {
                    assert!((a - b).abs() <= 1e-12 * largest, "{what}: W {a:e} vs {b:e}");
                }
                let n = k.dim();
                let mu: Vec<f64> = (0..rows.len()).map(|j| 1.0 + j as f64).collect();
                let (mut u_factor, mut u_cg) = (vec![0.5; n], vec![0.5; n]);
                factor.apply_correction(&mu, &mut u_factor).unwrap();
                cg.apply_correction(&mu, &mut u_cg).unwrap();
                let scale = u_factor.iter().fold(0.0_f64, |m, x| m.max((x - 0.5).abs()));
                for (a, b) in u_cg.iter().zip(&u_factor) {
                    assert!((a - b).abs() <= 1e-12 * scale, "{what}: u {a:e} vs {b:e}");
                }
            }
        }
    }
}

#[test]
fn the_adaptive_slab_stops_at_the_truncation_tolerance() {
    for b in [0.25, 1.0] {
        let (k, rows) = step_matrix("scenes/bar3d.json", 40, b, ContactTreatment::Multiplier);
        let slab = LocalDelassus::new(&k, &rows, None).unwrap().truncation();
        assert!(!slab.whole && slab.slab_dofs < k.dim(), "b = {b}: {slab:?}");
        assert!(slab.ratio <= 1e-14, "b = {b}: {slab:?}");
        // The predicted number of layers overshoots the smallest sufficient one by less than a
        // quarter (doubling stopped at 32 where about 19 suffice).
        let fewer = LocalDelassus::new(&k, &rows, Some(slab.layers * 4 / 5))
            .unwrap()
            .truncation();
        assert!(
            fewer.ratio > 1e-14,
            "b = {b}: {fewer:?} would have been enough"
        );
    }
}

#[test]
fn a_local_operator_needs_the_step_matrix() {
    let problem = box_problem("scenes/bar2d.json", ContactTreatment::Multiplier);
    let settings = solved_by(LinearSolver::Direct, ContactOperator::Local);
    let err = run(
        &problem,
        &config(10, Scheme::CRANK_NICOLSON, MassVariant::Standard, settings),
        &mut [],
    )
    .unwrap_err();
    assert!(err.to_string().contains("needs the step matrix"), "{err}");
}

fn config(nx: usize, scheme: Scheme, mass: MassVariant, settings: Settings) -> RunConfig {
    RunConfig {
        nx,
        ratio: 2.0,
        scheme,
        mass,
        observables: Observables::default(),
        settings,
    }
}

/// The largest `|a_k − b_k| / max_k |b_k|` over the energy, the mean and centre gaps, the total
/// force and the centre multiplier (relative to each series' scale: the contact force is
/// exactly zero between impacts).
fn worst_deviation(a: &BoxRun, b: &BoxRun) -> f64 {
    let energy = |r: &BoxRun| r.observed.energy.iter().map(|e| e.1).collect::<Vec<_>>();
    let series = [
        (energy(a), energy(b)),
        (
            a.observed.contact.mean_gap.clone(),
            b.observed.contact.mean_gap.clone(),
        ),
        (
            a.observed.contact.centre_gap.clone(),
            b.observed.contact.centre_gap.clone(),
        ),
        (
            a.observed.contact.total_force.clone(),
            b.observed.contact.total_force.clone(),
        ),
        (
            a.observed.contact.centre_multiplier.clone(),
            b.observed.contact.centre_multiplier.clone(),
        ),
    ];
    series
        .iter()
        .map(|(x, y)| {
            assert_eq!(x.len(), y.len());
            let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            x.iter()
                .zip(y)
                .map(|(p, q)| (p - q).abs() / scale)
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// Every scheme, mass and treatment of the cross-check on `scene` at level `nx`: the local
/// operator (a strict part of the system) within 1e-8 of the full one, one layer not.
fn cross_check(scene: &str, nx: usize) {
    let penalty = ContactTreatment::Penalty { gamma0: 10.0 };
    for contact in [ContactTreatment::Multiplier, penalty] {
        let problem = box_problem(scene, contact);
        let cg_with = |operator| solved_by(LinearSolver::Cg, operator);
        let run_cg = |operator, scheme, mass| {
            run(
                &problem,
                &config(nx, scheme, mass, cg_with(operator)),
                &mut [],
            )
            .unwrap()
            .completed()
            .unwrap()
        };
        for scheme in [Scheme::CRANK_NICOLSON, Scheme::BACKWARD_EULER] {
            for mass in [MassVariant::Standard, MassVariant::Redistributed] {
                let what = format!("{scene} {contact} {scheme} {mass}");
                let full = run_cg(ContactOperator::Full, scheme, mass);
                let local = run_cg(ContactOperator::Auto, scheme, mass);
                assert!(full.contact_solves > 0, "{what}: no impact");
                assert!(full.observed.contact_slab.is_none(), "{what}");
                let slab = local
                    .observed
                    .contact_slab
                    .expect("cg selects the local operator");
                assert!(!slab.whole && slab.ratio <= 1e-14, "{what}: {slab:?}");
                assert!(local.complementarity_violation <= 1e-10, "{what}");
                let deviation = worst_deviation(&local, &full);
                assert!(deviation <= 1e-8, "{what}: deviation {deviation:e}");
                // One layer is too thin a slab: the contact correction it computes is not the
                // step's, and the run's energy balance check says so.
                let thin_slab = cg_with(ContactOperator::LocalLayers(1));
                let thin = run(&problem, &config(nx, scheme, mass, thin_slab), &mut []).unwrap();
                assert!(
                    matches!(thin.status, RunStatus::SolverInaccurate { .. }),
                    "{what}: the one-layer slab passed as accurate: {:?}",
                    thin.status
                );
            }
        }
    }
}

#[test]
fn box_2d_runs_with_the_local_operator_match_the_full_one() {
    cross_check("scenes/bar2d.json", 80);
}

#[test]
fn box_3d_runs_with_the_local_operator_match_the_full_one() {
    cross_check("scenes/bar3d.json", 40);
}
