//! The slab-decomposed step solve of issue 36, ranks as threads ([`ThreadRanks`]): on 2D and
//! 3D box step matrices with either mass, a product with `K` and an application of the
//! preconditioner on `N` ranks equal the one-process ones entry for entry, bit for bit (they
//! sum nothing across ranks); a solve on one rank is the one-process solve bit for bit, and on
//! 2 to 4 ranks takes the same iterations and agrees to round-off (only the order of the inner
//! products' partial sums differs). A decomposition the layers cannot give is refused.

use signorini::engine::distributed::{DecompositionError, Ranks, SlabCg, Slabs, ThreadRanks};
use signorini::engine::fem::{BoxMesh, MassVariant};
use signorini::engine::linalg::{CgSpace, Pcg, PcgWork, DEFAULT_TOLERANCE};

use crate::slabs::{level_40, relative, start_of, step_matrix};

fn boxes() -> Vec<BoxMesh> {
    vec![
        BoxMesh::new(&[0.2, 1.0], &[4, 20]).unwrap(),
        BoxMesh::new(&[0.1, 0.1, 1.0], &[3, 2, 16]).unwrap(),
    ]
}

fn random(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = fastrand::Rng::with_seed(seed);
    (0..n).map(|_| rng.f64() - 0.5).collect()
}

/// What each rank returns: its range of the unknowns and its part of a vector.
type Parts = Vec<(std::ops::Range<usize>, Vec<f64>)>;

/// The whole vector from the ranks' parts, checking that they tile it.
fn assemble(n: usize, parts: Parts) -> Vec<f64> {
    let mut whole = Vec::with_capacity(n);
    for (range, part) in parts {
        assert_eq!(range.start, whole.len(), "the slabs tile the unknowns");
        assert_eq!(range.len(), part.len());
        whole.extend(part);
    }
    assert_eq!(whole.len(), n);
    whole
}

#[test]
fn products_and_preconditioner_on_slabs_equal_the_one_process_ones_bit_for_bit() {
    for mesh in boxes() {
        for variant in [MassVariant::Redistributed, MassVariant::Standard] {
            let k = step_matrix(&mesh, variant);
            let n = k.dim();
            let whole = Pcg::new(k.clone(), DEFAULT_TOLERANCE, "K").unwrap();
            let x = random(n, 36);
            let (mut kx, mut px) = (vec![0.0; n], vec![0.0; n]);
            whole.mul_dot(&x, &mut kx);
            whole.precondition(&x, &mut px);
            for ranks in 1..=4 {
                let parts = ThreadRanks::run(ranks, |r| {
                    let cg = SlabCg::new(r, &k, 1, DEFAULT_TOLERANCE).unwrap();
                    let own = cg.own_dofs();
                    let (mut y, mut z) = (vec![0.0; own.len()], vec![0.0; own.len()]);
                    cg.mul_dot(&x[own.clone()], &mut y);
                    cg.precondition(&x[own.clone()], &mut z);
                    (own, y, z)
                });
                let (products, preconditioned): (Parts, Parts) = parts
                    .into_iter()
                    .map(|(own, y, z)| ((own.clone(), y), (own, z)))
                    .unzip();
                let what = format!("{:?} {variant:?} on {ranks} ranks", mesh.counts());
                assert!(assemble(n, products) == kx, "K x, {what}");
                assert!(assemble(n, preconditioned) == px, "P⁻¹ x, {what}");
            }
        }
    }
}

#[test]
fn a_solve_on_slabs_is_the_one_process_solve() {
    for mesh in boxes() {
        for variant in [MassVariant::Redistributed, MassVariant::Standard] {
            let k = step_matrix(&mesh, variant);
            let n = k.dim();
            let b = random(n, 7);
            let guess = random(n, 8);
            let whole = Pcg::new(k.clone(), DEFAULT_TOLERANCE, "K").unwrap();
            let mut expected = guess.clone();
            let iterations = whole
                .solve(&b, &mut expected, &mut PcgWork::new(n))
                .unwrap();
            let scale = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for ranks in 1..=4 {
                let parts = ThreadRanks::run(ranks, |r| {
                    let cg = SlabCg::new(r, &k, 1, DEFAULT_TOLERANCE).unwrap();
                    let own = cg.own_dofs();
                    let mut x = guess[own.clone()].to_vec();
                    let spent = cg
                        .solve(&b[own.clone()], &mut x, &mut PcgWork::new(own.len()))
                        .unwrap();
                    (own, x, spent)
                });
                let what = format!("{:?} {variant:?} on {ranks} ranks", mesh.counts());
                assert!(
                    parts.iter().all(|(_, _, spent)| *spent == iterations),
                    "{what}: iterations {:?}, one process {iterations}",
                    parts.iter().map(|p| p.2).collect::<Vec<_>>()
                );
                let x = assemble(n, parts.into_iter().map(|(o, x, _)| (o, x)).collect());
                if ranks == 1 {
                    assert!(x == expected, "{what}: not bit for bit");
                }
                let worst = x
                    .iter()
                    .zip(&expected)
                    .map(|(p, q)| (p - q).abs())
                    .fold(0.0, f64::max);
                assert!(worst <= 1e-12 * scale, "{what}: {worst:e} of {scale:e}");
            }
        }
    }
}

#[test]
fn a_decomposition_the_layers_cannot_give_is_refused() {
    assert_eq!(Slabs::even(10, 0, 1), Err(DecompositionError::NoRanks));
    let slabs = Slabs::even(10, 3, 5).unwrap();
    assert_eq!(
        (0..3).map(|r| slabs.of(r)).collect::<Vec<_>>(),
        [0..5, 5..8, 8..10]
    );
    let refused = Slabs::even(10, 7, 5).unwrap_err();
    assert_eq!(
        refused,
        DecompositionError::TooManyRanks {
            ranks: 7,
            layers: 10,
            most: 6,
            first_layers: 5
        }
    );
    assert!(refused.to_string().contains("at most 6 ranks"), "{refused}");
    let mesh = BoxMesh::new(&[0.1, 1.0], &[1, 4]).unwrap();
    let k = step_matrix(&mesh, MassVariant::Redistributed);
    let refused = ThreadRanks::run(4, |r| SlabCg::new(r, &k, 1, DEFAULT_TOLERANCE).err());
    assert!(
        refused
            .iter()
            .all(|e| matches!(e, Some(DecompositionError::TooManyRanks { most: 3, .. }))),
        "{refused:?}"
    );
}

/// Crank–Nicolson with `M^mod` on the note's 2D and 3D bars at level 40 (the reference's
/// scheme, solved with `cg`), over `T = 1` (the impact at `t = 0.4` included): `N` ranks
/// against [`OneStepScheme`] on the whole box. Energies, contact multipliers and the final
/// displacement are the one-process ones bit for bit on one rank, and to 1e-10 of their scale
/// on 2 and 3 ranks, in as many CG iterations.
#[test]
fn a_crank_nicolson_run_on_slabs_is_the_one_process_run() {
    use crate::stepper::Stepper;
    use signorini::engine::distributed::SlabOneStep;
    use signorini::engine::schemes::conventions::{NitscheAcceleration, PredictorForm};
    use signorini::engine::schemes::{OneStepScheme, SchemeState, StepCoefficients};
    use signorini::harness::study::scene::Scene;

    for scene in ["scenes/bar2d.json", "scenes/bar3d.json"] {
        let mut problem = Scene::load(std::path::Path::new(scene))
            .unwrap()
            .box_problem("a box")
            .unwrap();
        problem.horizon = 1.0;
        let discretisation = level_40(&problem);
        let model = &discretisation.model;
        let coef = StepCoefficients::newmark(0.25, 0.5);
        let dt = 1.0 / 40.0 / 2.0;
        let steps = 80;
        let start = start_of(&discretisation);
        let mut whole = Stepper::new(
            OneStepScheme::new(model, coef, dt, NitscheAcceleration::Consistent).unwrap(),
            SchemeState::start(dt, start.clone()),
        );
        let mut energy = vec![whole.energy().value];
        let mut lambda = vec![whole.lambda.clone()];
        for _ in 0..steps {
            whole.advance().unwrap();
            energy.push(whole.energy().value);
            lambda.push(whole.lambda.clone());
        }
        let u = whole.u.clone();
        let iterations = whole.statistics().step_solves.iterations;
        let force_scale = lambda.iter().flatten().fold(0.0_f64, |m, l| m.max(l.abs()));
        assert!(force_scale > 0.0, "{scene}: the bar hits the obstacle");
        let u_scale = u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for ranks in 1..=3 {
            let parts = ThreadRanks::run(ranks, |r| {
                let mut run = SlabOneStep::new(
                    r,
                    model,
                    coef,
                    dt,
                    (r.rank() == 0).then_some(&start),
                    PredictorForm::Expanded,
                )
                .unwrap();
                let mut energy = vec![run.energy()];
                let mut lambda = vec![run.multipliers().to_vec()];
                for _ in 0..steps {
                    run.advance().unwrap();
                    energy.push(run.energy());
                    lambda.push(run.multipliers().to_vec());
                }
                let spent = run.statistics().step_solves.iterations;
                (
                    run.own_dofs(),
                    run.displacement().to_vec(),
                    energy,
                    lambda,
                    spent,
                )
            });
            let what = format!("{scene} on {ranks} ranks");
            let (_, _, slab_energy, slab_lambda, _) = &parts[0];
            assert!(
                parts.iter().all(|p| p.4 == iterations),
                "{what}: iterations"
            );
            assert!(
                parts.iter().all(|p| p.2 == *slab_energy),
                "{what}: ranks' energies"
            );
            let slab_u = assemble(
                u.len(),
                parts.iter().map(|p| (p.0.clone(), p.1.clone())).collect(),
            );
            if ranks == 1 {
                assert!(*slab_energy == energy, "{what}: energy not bit for bit");
                assert!(*slab_lambda == lambda, "{what}: λ not bit for bit");
                assert!(slab_u == u, "{what}: U not bit for bit");
            }
            let worst = |a: &[f64], b: &[f64]| {
                a.iter()
                    .zip(b)
                    .map(|(p, q)| (p - q).abs())
                    .fold(0.0, f64::max)
            };
            let e_scale = energy.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
            let e_worst = worst(slab_energy, &energy);
            let l_worst = slab_lambda
                .iter()
                .zip(&lambda)
                .map(|(p, q)| worst(p, q))
                .fold(0.0, f64::max);
            let u_worst = worst(&slab_u, &u);
            assert!(e_worst <= 1e-10 * e_scale, "{what}: energy {e_worst:e}");
            assert!(l_worst <= 1e-10 * force_scale, "{what}: λ {l_worst:e}");
            assert!(u_worst <= 1e-10 * u_scale, "{what}: U {u_worst:e}");
            println!(
                "{what}: energy {:.1e}, λ {:.1e}, U {:.1e} (relative)",
                e_worst / e_scale,
                l_worst / force_scale,
                u_worst / u_scale
            );
        }
    }
}

/// The 3D bar's reference on 40 elements (projected on levels 10 and 20) computed by rank 0
/// of `N` thread ranks ([`FineReference::obtain`] with the ranks, the others following) against
/// the one-process reference: every history, check distance and projection bit for bit on one
/// rank, to 1e-10 of its scale on 2 and 3. Its check run on 20 elements cannot be cut (its
/// contact slab takes every layer), so on 2 and 3 ranks it runs in one process beside rank 0.
#[test]
fn a_reference_on_ranks_is_the_one_process_reference() {
    reference_on_ranks_against_one_process(40, &[10, 20], &[(1, 1), (2, 1), (3, 1)]);
}

/// The reference on 80 elements on two thread ranks: its check run on 40 elements is
/// distributed over them too (a step of it every second reference step, on every rank), and
/// the reference is still the one-process one to 1e-10.
#[test]
fn a_reference_on_two_ranks_shares_its_check_run_with_them() {
    reference_on_ranks_against_one_process(80, &[20, 40], &[(2, 2)]);
}

/// The 3D bar's reference on `level` elements projected on `levels`, computed by rank 0 of
/// `ranks` thread ranks, its check run shared by `check_ranks` of them, for each case
/// `(ranks, check_ranks)`, against the one-process reference: bit for bit on one rank, to
/// 1e-10 of each value's scale otherwise.
fn reference_on_ranks_against_one_process(
    level: usize,
    levels: &[usize],
    cases: &[(usize, usize)],
) {
    use signorini::engine::linalg::LinearSolver;
    use signorini::harness::reference::fine_mesh::cache::ReferenceCache;
    use signorini::harness::reference::fine_mesh::fine_run::FineReference;
    use signorini::harness::reference::fine_mesh::{reference_key, ElasticStudyConfig};
    use signorini::harness::study::scene::Scene;

    let scene = Scene::load(std::path::Path::new("scenes/bar3d.json")).unwrap();
    let problem = scene.box_problem("a box").unwrap();
    let mut config = ElasticStudyConfig::from_scene(&scene, Some(level)).unwrap();
    config.levels = levels.to_vec();
    config.settings.linear_solver = LinearSolver::Cg;
    let key = reference_key(&problem, &config).unwrap();
    let settings = config.settings;
    let whole = FineReference::compute(&problem, &settings, key.clone(), None).unwrap();
    let empty = std::env::temp_dir().join(format!("signorini-no-cache-{}", std::process::id()));
    for &(ranks, check_ranks) in cases {
        let computed = ThreadRanks::run(ranks, |r| {
            if r.rank() > 0 {
                FineReference::follow(&problem, &settings, &key, r).unwrap();
                return None;
            }
            let cache = ReferenceCache::ReadOnly(empty.clone());
            Some(
                FineReference::obtain(
                    &problem,
                    &settings,
                    (&cache, key.clone()),
                    &mut |_| {},
                    &|| Ok(()),
                    Some(r),
                )
                .unwrap(),
            )
        });
        let reference = computed[0].as_ref().expect("rank 0's reference");
        assert_eq!(
            reference.cost.map(|c| c.check_ranks),
            Some(check_ranks),
            "the ranks of the check run"
        );
        let (h, w) = (&reference.histories, &whole.histories);
        let what = format!("{ranks} ranks");
        let series = [
            ("energy", &h.energy, &w.energy),
            ("total force", &h.total_force, &w.total_force),
            (
                "centre displacement",
                &h.centre_displacement,
                &w.centre_displacement,
            ),
            (
                "centre multiplier",
                &h.centre_multiplier,
                &w.centre_multiplier,
            ),
        ];
        assert_eq!(h.time, w.time, "{what}");
        assert_eq!((h.dofs, h.steps, h.dt), (w.dofs, w.steps, w.dt), "{what}");
        let projections: Vec<(f64, bool)> = reference
            .projections
            .iter()
            .zip(&whole.projections)
            .map(|(p, q)| {
                let (p, q): (Vec<f64>, Vec<f64>) = (p.values().collect(), q.values().collect());
                (relative(&p, &q), p == q)
            })
            .collect();
        let distances: Vec<f64> = h.check.distance.values().copied().collect();
        let expected: Vec<f64> = w.check.distance.values().copied().collect();
        if ranks == 1 {
            for (name, a, b) in series {
                assert!(a == b, "{what}: {name} not bit for bit");
            }
            assert!(projections.iter().all(|p| p.1), "{what}: projections");
            assert_eq!(distances, expected, "{what}: check");
        }
        for (name, a, b) in series {
            assert!(
                relative(a, b) <= 1e-10,
                "{what}: {name} {:e}",
                relative(a, b)
            );
        }
        assert!(
            projections.iter().all(|p| p.0 <= 1e-10),
            "{what}: {projections:?}"
        );
        assert!(relative(&distances, &expected) <= 1e-10, "{what}: check");
    }
}

/// The communication of a solve, counted ([`CountedRanks`]), is what the cost model of
/// docs/src/distributed-reference.md charges a solve of `k` iterations: on rank 0 of two,
/// `k + 2` halo exchanges of one layer (one product per iteration, the true residual before
/// and after), `k` downward sweeps of [`SWEEP_CHUNKS`] chunks of a layer (one preconditioner
/// application per iteration; rank 0 sends nothing upwards), and `3k + 3` sums.
#[test]
fn a_solve_on_two_ranks_exchanges_what_the_cost_model_charges() {
    use signorini::engine::distributed::{CountedRanks, Traffic};
    const SWEEP_CHUNKS: u64 = 8;
    let mesh = BoxMesh::new(&[0.1, 0.1, 1.0], &[3, 2, 16]).unwrap();
    let k = step_matrix(&mesh, MassVariant::Redistributed);
    let layer_bytes = (4 * 3 * 3 * 8) as u64;
    let b = random(k.dim(), 5);
    let counted = ThreadRanks::run(2, |r| {
        let counted = CountedRanks::new(r);
        let cg = SlabCg::new(&counted, &k, 1, DEFAULT_TOLERANCE).unwrap();
        let own = cg.own_dofs();
        let before = counted.traffic();
        let mut x = vec![0.0; own.len()];
        let iterations = cg
            .solve(&b[own.clone()], &mut x, &mut PcgWork::new(own.len()))
            .unwrap() as u64;
        let after = counted.traffic();
        (
            iterations,
            Traffic {
                messages: after.messages - before.messages,
                bytes_sent: after.bytes_sent - before.bytes_sent,
                bytes_received: after.bytes_received - before.bytes_received,
                sums: after.sums - before.sums,
            },
        )
    });
    let (iterations, traffic) = counted[0];
    assert!(iterations > 2, "{iterations}");
    assert_eq!(
        traffic,
        Traffic {
            messages: (iterations + 2) + iterations * SWEEP_CHUNKS,
            bytes_sent: (iterations + 2) * layer_bytes + iterations * layer_bytes,
            bytes_received: (iterations + 2) * layer_bytes + iterations * layer_bytes,
            sums: 3 * iterations + 3,
        }
    );
}

/// The memory budget of a reference across ranks: every rank's estimate with the others' on
/// its machine (thread ranks share one). A limit that holds rank 1's and not rank 0's stops
/// both before anything is computed: rank 0 says why, rank 1 that another rank refused.
#[test]
fn a_reference_whose_rank_does_not_fit_its_machine_is_refused_on_every_rank() {
    use signorini::commands::{references, ReferenceRequest};
    use signorini::engine::linalg::LinearSolver;
    use signorini::harness::reference::fine_mesh::ElasticStudyConfig;
    use signorini::harness::study::budget::{reference_rank, Limits};
    use signorini::harness::study::executor::Executor;
    use signorini::harness::study::scene::Scene;
    use signorini::harness::study::shard::Invocation;

    let path = std::path::PathBuf::from("scenes/bar3d.json");
    let scene = Scene::load(&path).unwrap();
    let problem = scene.box_problem("a box").unwrap();
    let config = ElasticStudyConfig::from_scene(&scene, None).unwrap();
    let rank_bytes = reference_rank(&problem, config.reference_level, 2).memory_bytes;
    let limit = (2.0 * rank_bytes) as u64 + 1;
    let cache = std::env::temp_dir().join(format!("signorini-rank-budget-{}", std::process::id()));
    let invocation = Invocation {
        command: "reference".into(),
        arguments: vec![],
        request: String::new(),
        inputs: vec![],
    };
    let said = ThreadRanks::run(2, |r| {
        let request = ReferenceRequest {
            scenes: vec![path.clone()],
            cache: Some(cache.clone()),
            out: None,
            linear_solver: LinearSolver::Cg,
            limits: Limits::or_defaults(Some(limit), None, None),
            ranks: Some(r),
            measure: None,
        };
        references(request, &Executor::Local, &invocation, &|_| {})
            .err()
            .map(|e| e.to_string())
    });
    let rank0 = said[0].as_deref().expect("rank 0 refuses");
    assert!(
        rank0.contains("rank 0 of 2") && rank0.contains("--max-memory"),
        "{rank0}"
    );
    let rank1 = said[1].as_deref().expect("rank 1 stops with it");
    assert!(rank1.contains("another rank"), "{rank1}");
    assert!(!cache.exists(), "nothing is computed or cached");
}

/// The energy balance of a distributed run is checked on the slabs (eq. 33 for
/// Crank–Nicolson): its largest relative residual over the 3D bar's run at level 40, impact
/// included, is at round-off as the one-process run's is, and a step the slabs get wrong would
/// stop the run (the same monitor and tolerance).
#[test]
fn a_distributed_run_checks_its_energy_balance_on_the_slabs() {
    use signorini::engine::linalg::LinearSolver;
    use signorini::harness::problem::Settings;
    use signorini::harness::run::distributed::{distributed_run, follow_run};
    use signorini::harness::run::elastic::run_box;
    use signorini::harness::run::{Observables, RunConfig};
    use signorini::harness::study::scene::Scene;

    let mut problem = Scene::load(std::path::Path::new("scenes/bar3d.json"))
        .unwrap()
        .box_problem("a box")
        .unwrap();
    problem.horizon = 1.0;
    let config = RunConfig {
        nx: 40,
        ratio: 2.0,
        scheme: "crank-nicolson".parse().unwrap(),
        mass: MassVariant::Redistributed,
        observables: Observables::default(),
        settings: Settings {
            linear_solver: LinearSolver::Cg,
            ..Settings::default()
        },
    };
    let whole = run_box(&problem, (&config, None), &mut [])
        .unwrap()
        .max_balance_residual
        .expect("the one-process run is balanced");
    let residuals = ThreadRanks::run(2, |r| {
        if r.rank() > 0 {
            follow_run(&problem, &config, (r, &[])).unwrap();
            return None;
        }
        let make = distributed_run(r, &[]);
        run_box(&problem, (&config, Some(&*make)), &mut [])
            .unwrap()
            .max_balance_residual
    });
    let distributed = residuals[0].expect("the distributed run is balanced");
    assert!(
        distributed > 0.0 && distributed < 1e-11 && whole < 1e-11,
        "{distributed:e} on two ranks, {whole:e} in one process"
    );
}

/// A non-finite value on any rank ends the run on every rank, naming the quantity: the 3D
/// bar's initial velocity with a NaN in its last unknown, which rank 1 holds, stops both ranks
/// before the first step.
#[test]
fn a_non_finite_value_on_one_rank_stops_every_rank() {
    use signorini::engine::error::{SolveError, StateField};
    use signorini::harness::files::error::Error;
    use signorini::harness::run::distributed::DistributedRun;
    use signorini::harness::study::scene::Scene;

    let problem = Scene::load(std::path::Path::new("scenes/bar3d.json"))
        .unwrap()
        .box_problem("a box")
        .unwrap();
    let discretisation = level_40(&problem);
    let mut velocity = discretisation.velocity.clone();
    *velocity.last_mut().unwrap() = f64::NAN;
    let outcomes = ThreadRanks::run(2, |r| {
        DistributedRun::new(
            (r, &[]),
            &discretisation.model,
            ("crank-nicolson".parse().unwrap(), 1.0 / 80.0),
            (r.rank() == 0).then_some((&discretisation.displacement[..], &velocity[..])),
            &discretisation.conventions,
        )
        .err()
        .map(|e| e.to_string())
    });
    let expected = Error::from(SolveError::NonFinite {
        step: 0,
        time: 0.0,
        quantity: StateField::Velocity,
    })
    .to_string();
    for (rank, outcome) in outcomes.iter().enumerate() {
        assert_eq!(outcome.as_deref(), Some(expected.as_str()), "rank {rank}");
    }
}
