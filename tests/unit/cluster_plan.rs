//! The cluster plan's cost model (`studies::cluster_plan::fit`): fitted to measurements that a
//! known model produced, it gives that model back, and it refuses too few measurements.

use signorini::studies::cluster_plan::fit::{CostModel, Node};
use signorini::studies::cluster_plan::measurement::{MeasuredTraffic, MEASUREMENT_FORMAT};
use signorini::studies::cluster_plan::Measurement;

/// The coefficients the synthetic measurements are made with.
const A: f64 = 2.0e-8;
const C: f64 = 3.0e-3;
/// Contact seconds per step and contact slab unknown, and the slab's layers.
const E: f64 = 1.0e-7;
const L: usize = 21;
const ITERATIONS: [(usize, usize); 2] = [(80, 10), (160, 9)];

/// The iterations per step through both measured levels, `k = 10 (ℓ/80)^log₂0.9`.
fn iterations(level: usize) -> f64 {
    10.0 * (level as f64 / 80.0).powf(0.9f64.log2())
}

/// The known model's seconds per step of rank 0 of a run on `level` (`dofs` unknowns) over
/// `ranks` ranks: its layers' CG work, the contact on its slab, and the step.
fn step_seconds(level: usize, dofs: usize, ranks: usize) -> f64 {
    let layer = dofs as f64 / level as f64;
    let own = level.div_ceil(ranks).max(L + 1).min(level) as f64;
    A * iterations(level) * layer * own + E * layer * (L + 1) as f64 + C
}

/// A run of `level` (3D bar: `3 (ℓ/10 + 1)² ℓ` unknowns, `2ℓ` steps) on `ranks` ranks of
/// `threads` threads, its time and memory those of the known model: on several ranks, the
/// check run (`level / 2`) distributed over them adds half a step of it.
fn measured(level: usize, ranks: usize, threads: usize) -> Measurement {
    let side = level / 10 + 1;
    let dofs = 3 * side * side * level;
    let check_dofs = 3 * (level / 20 + 1).pow(2) * (level / 2);
    let steps = 2 * level;
    let k = ITERATIONS.iter().find(|(l, _)| *l == level).unwrap().1;
    let n = dofs as f64;
    let mut per_step = step_seconds(level, dofs, ranks);
    if ranks > 1 {
        per_step += 0.5 * step_seconds(level / 2, check_dofs, ranks);
    }
    let contact_per_step = E * n / level as f64 * (L + 1) as f64;
    let peak = |rank: usize| {
        let (fixed, whole, slab, per_rank) = if rank == 0 {
            (80e6, 400.0, 120.0, 2e6)
        } else {
            (20e6, 200.0, 180.0, 3e6)
        };
        (fixed + whole * n + slab * n / ranks as f64 + per_rank * ranks as f64) as u64
    };
    Measurement {
        format: MEASUREMENT_FORMAT.to_string(),
        scene: "bar3d".into(),
        level,
        dofs,
        steps,
        ranks,
        threads,
        check_ranks: ranks,
        check_dofs,
        setup_seconds: 1e-6 * n,
        step_seconds: per_step * steps as f64,
        contact_seconds: contact_per_step * steps as f64,
        contact_layers: Some(L),
        observe_seconds: 0.0,
        solves: steps,
        iterations: k * steps,
        peak_bytes: (0..ranks).map(peak).collect(),
        traffic: (ranks > 1).then_some(MeasuredTraffic {
            messages: (10 * k * steps) as u64,
            bytes_sent: (23 * k * steps * dofs / level) as u64,
            bytes_received: 0,
            sums: (4 * k * steps) as u64,
        }),
    }
}

fn runs() -> Vec<Measurement> {
    let mut runs = Vec::new();
    for (level, _) in ITERATIONS {
        runs.push(measured(level, 1, 1));
        runs.push(measured(level, 2, 1));
        runs.push(measured(level, 3, 1));
        runs.push(measured(level, 4, 1));
    }
    runs
}

#[test]
fn the_model_fitted_to_its_own_measurements_is_that_model() {
    let model = CostModel::fit(&runs(), 2).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs();
    assert!(
        close(model.per_iteration_dof, A),
        "{}",
        model.per_iteration_dof
    );
    assert!(close(model.per_step, C), "{}", model.per_step);
    assert!(close(model.contact_per_slab_dof, E));
    assert_eq!(model.contact_layers, L);
    assert!(close(model.rank0_memory.per_dof, 400.0));
    assert!(close(model.rank0_memory.per_slab_dof, 120.0));
    assert!(close(model.rank_memory.per_dof, 200.0));
    assert!(close(model.rank_memory.per_slab_dof, 180.0));
    assert!(close(model.rank0_memory.per_rank, 2e6) && close(model.rank_memory.per_rank, 3e6));
    assert!(close(model.messages_per_iteration, 10.0));
    assert!(close(model.sums_per_iteration, 4.0));
    // Three and four ranks on two cores are oversubscribed: fitted for memory, not time.
    assert!(model.time_fit.iter().all(|&(_, ranks, _, _)| ranks <= 2));
    for &(_, _, measured, modelled) in &model.time_fit {
        assert!(close(modelled, measured), "{modelled} vs {measured}");
    }
    // Nine iterations at 160 and ten at 80: k = k0 ℓ^p through both.
    assert!(close(model.iterations_at(80), 10.0) && close(model.iterations_at(160), 9.0));
}

#[test]
fn the_interconnect_costs_nothing_on_one_rank_and_grows_with_the_ranks() {
    let model = CostModel::fit(&runs(), 2).unwrap();
    let node = Node {
        cores: 64,
        memory_bytes: 256e9,
        bandwidth: 12.5e9,
        latency: 2e-6,
    };
    let n = 6.4e7;
    assert_eq!(model.network_seconds(&node, 1280, n, 1.0), 0.0);
    // The check run takes half a step of one eighth of the unknowns; rank 0 holds the contact
    // slab's layers however many ranks share the box.
    let check = model.check_seconds(1280, n / 8.0, 64.0);
    assert!((check - 0.5 * model.step_seconds(640, n / 8.0, 64.0)).abs() < 1e-15);
    assert_eq!(model.rank0_layers(1280, 8.0), 160);
    assert_eq!(model.rank0_layers(1280, 512.0), L + 1);
    let few = model.network_seconds(&node, 1280, n, 8.0);
    let many = model.network_seconds(&node, 1280, n, 512.0);
    assert!(few > 0.0 && many > few, "{few} then {many}");
}

#[test]
fn too_few_measurements_are_refused_with_what_the_model_needs() {
    let only_one_level: Vec<Measurement> = runs().into_iter().filter(|m| m.level == 80).collect();
    let err = CostModel::fit(&only_one_level, 2).unwrap_err();
    assert!(err.0.contains("needs two"), "{}", err.0);
    let one_rank: Vec<Measurement> = runs().into_iter().filter(|m| m.ranks == 1).collect();
    assert!(CostModel::fit(&one_rank, 2).is_err());
}

/// `signorini cluster-plan` end to end on measurements written as `--measure` writes them:
/// the plan's JSON has its documented fields, one prediction per number of nodes, each rank
/// count within the layers and each node's memory within the stated node's.
#[test]
fn the_plan_command_writes_a_prediction_per_number_of_nodes() {
    let dir = std::env::temp_dir().join(format!("signorini-plan-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files: Vec<String> = runs()
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let path = dir.join(format!("m{i}.json"));
            m.write(&path).unwrap();
            path.to_str().unwrap().to_string()
        })
        .collect();
    let out = dir.join("plan");
    let mut args = vec![
        "cluster-plan",
        "scenes/bar3d.json",
        "--level",
        "640",
        "--measured-cores",
        "2",
        "--nodes",
        "2,4",
        "--memory",
        "64G",
        "--out",
        out.to_str().unwrap(),
        "--measured",
    ];
    args.extend(files.iter().map(String::as_str));
    let said = crate::common::success_stdout(&crate::common::signorini(&args));
    assert!(said.contains("cluster-plan.md"), "{said}");
    let plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("cluster-plan.json")).unwrap())
            .unwrap();
    let predictions = plan["predictions"].as_array().unwrap();
    assert_eq!(predictions.len(), 2);
    // Beyond ℓ/(L + 1) ranks rank 0's contact slab bounds the step: four nodes are given
    // no more ranks than two.
    assert_eq!(predictions[0]["ranks"], predictions[1]["ranks"], "{plan}");
    for (p, nodes) in predictions.iter().zip([2, 4]) {
        assert_eq!(p["nodes"], nodes);
        let ranks = p["ranks"].as_u64().unwrap();
        assert!((1..=320).contains(&ranks), "{p}");
        assert!(
            p["node_bytes"].as_f64().unwrap() <= 64.0 * f64::from(1u32 << 30),
            "{p}"
        );
        let hours = p["hours"].as_f64().unwrap();
        assert!(hours.is_finite() && hours > 0.0, "{p}");
        for field in [
            "ranks_per_node",
            "rank0_bytes",
            "rank_bytes",
            "slab_seconds_per_step",
            "network_seconds_per_step",
            "check_seconds_per_step",
        ] {
            assert!(p[field].is_number(), "{field} in {p}");
        }
    }
    assert!(plan["model"]["per_iteration_dof"].is_number());
    assert!(std::fs::read_to_string(out.join("cluster-plan.md"))
        .unwrap()
        .contains("## The prediction"));
    let _ = std::fs::remove_dir_all(&dir);
}
