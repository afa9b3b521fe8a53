//! Another code's runs made from the harness's own: a scheme run on the Dirichlet scene, every
//! state exported in the external-run format (docs/src/external-runs.md), JSON or CSV, by a
//! writer independent of the harness's reader.

use std::path::Path;
use std::time::Instant;

use signorini::engine::fem::MassVariant;
use signorini::engine::problem::{Problem1d, Settings};
use signorini::engine::schemes::{Integration, Scheme};
use signorini::harness::files::error::Error;
use signorini::harness::run::{drive, Observer};

/// The Dirichlet scene's file and name.
pub const SCENE: &str = "scenes/bar1d-dirichlet.json";
/// The name in it.
pub const SCENE_NAME: &str = "bar1d-dirichlet";

/// Every state of one run, node by node.
pub struct Export {
    /// The mesh nodes.
    pub nodes: Vec<f64>,
    /// `t_n`.
    pub time: Vec<f64>,
    /// `u_h(x_i, t_n)`, all nodes (the clamped one's 0).
    pub displacement: Vec<Vec<f64>>,
    /// `v_h(x_i, t_n)`.
    pub velocity: Vec<Vec<f64>>,
    /// `λ_h` with its time.
    pub lambda: Vec<(f64, f64)>,
    /// `E_h` with its time.
    pub energy: Vec<(f64, f64)>,
}

/// Runs `scheme` with `mass` on `problem` at `nx` (Δx/Δt = `ratio`) through the harness's
/// time loop with its default settings and records every state.
pub fn export_run(
    problem: &Problem1d,
    nx: usize,
    ratio: f64,
    scheme: Scheme,
    mass: MassVariant,
) -> Export {
    export_run_with(problem, nx, ratio, (scheme, mass), &Settings::default())
}

/// [`export_run`] of the case `(scheme, mass)` solved with `settings` (another start, for one).
pub fn export_run_with(
    problem: &Problem1d,
    nx: usize,
    ratio: f64,
    (scheme, mass): (Scheme, MassVariant),
    settings: &Settings,
) -> Export {
    let d = problem.discretise(nx, mass, settings).unwrap();
    let bar = d.mesh.clone();
    let mut e = Export {
        nodes: (0..=nx).map(|i| bar.node(i)).collect(),
        time: Vec::new(),
        displacement: Vec::new(),
        velocity: Vec::new(),
        lambda: Vec::new(),
        energy: Vec::new(),
    };
    let mut record = |s: &Integration| -> Result<(), Error> {
        let nodal = |f: &[f64]| (0..=nx).map(|i| bar.nodal_value(f, i)).collect();
        e.time.push(s.time());
        e.displacement.push(nodal(s.displacement()));
        e.velocity.push(nodal(s.velocity()));
        let m = s.multiplier();
        e.lambda.push((m.time, m.value[0]));
        let en = s.energy();
        e.energy.push((en.time, en.value));
        Ok(())
    };
    let mut observers: [&mut dyn Observer; 1] = [&mut record];
    drive(
        &d,
        problem.horizon,
        ratio,
        scheme,
        &mut observers,
        Instant::now(),
    )
    .unwrap();
    e
}

/// `e` as a JSON run file at `path`, with `lambda_time` and `energy_time`.
pub fn write_json(path: &Path, e: &Export, label: &str) {
    let samples: Vec<serde_json::Value> = (0..e.time.len())
        .map(|k| {
            serde_json::json!({
                "time": e.time[k],
                "displacement": e.displacement[k],
                "velocity": e.velocity[k],
                "lambda": e.lambda[k].1,
                "lambda_time": e.lambda[k].0,
                "energy": e.energy[k].1,
                "energy_time": e.energy[k].0,
            })
        })
        .collect();
    let file = serde_json::json!({
        "format": "signorini-external/1",
        "scene": SCENE_NAME,
        "code": {"name": "signorini", "version": "test export"},
        "label": label,
        "mesh": {"nodes": e.nodes},
        "samples": samples,
    });
    std::fs::write(path, serde_json::to_string(&file).unwrap()).unwrap();
}

/// `e` as a CSV run file at `path` (times of λ and E are the samples'; checked).
pub fn write_csv(path: &Path, e: &Export, label: &str) {
    let n = e.nodes.len();
    let nodes: Vec<String> = e.nodes.iter().map(|x| x.to_string()).collect();
    let mut text = format!(
        "# format: signorini-external/1\n# scene: {SCENE_NAME}\n# code.name: signorini\n\
         # code.version: test export\n# label: {label}\n# mesh.nodes: {}\ntime",
        nodes.join(", ")
    );
    for p in ["u", "v"] {
        for i in 0..n {
            text.push_str(&format!(",{p}{i}"));
        }
    }
    text.push_str(",lambda,energy\n");
    for k in 0..e.time.len() {
        assert_eq!(e.lambda[k].0, e.time[k], "λ at the sample's time");
        assert_eq!(e.energy[k].0, e.time[k], "E at the sample's time");
        let mut row = vec![e.time[k].to_string()];
        row.extend(e.displacement[k].iter().map(|x| x.to_string()));
        row.extend(e.velocity[k].iter().map(|x| x.to_string()));
        row.push(e.lambda[k].1.to_string());
        row.push(e.energy[k].1.to_string());
        text.push_str(&row.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
}
