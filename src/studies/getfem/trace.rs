//! GetFEM's runs as another code's runs: each finite run is a contact trace of the
//! external-run format (docs/src/external-runs.md). [`trace_norms`] measures the trace as
//! version 1 reads it (the demo's stored values, its energy in the energy norms), in place;
//! [`export_runs`] writes it for `signorini verify` in version 2, declaring what the demo
//! computed ([`declared_trace`]).

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::harness::external::format::{
    Code, EnergyDefinition, ExternalRun, SampleOrigin, Version, FORMAT_2,
};
use crate::harness::external::replay::{replay, EnergySource};
use crate::harness::files::artifacts::write_atomic;
use crate::harness::getfem::DemoRunError;
use crate::harness::getfem::{list_runs, read_run, DemoRun, DemoVersion};
use crate::harness::run::norms::Norm;
use crate::harness::study::budget::{Estimate, Limits};
use crate::studies::benchmark::dirichlet;
use crate::studies::error::Error;

/// The scene every demo run solves.
const SCENE: &str = "bar1d-dirichlet";

/// The norms a contact trace has the data of: the multiplier's and the energy's.
pub const TRACE_NORMS: [Norm; 3] = [Norm::MultiplierL2, Norm::EnergyLinf, Norm::EnergyL2];

/// The configuration's label of a run file: its name without the directory, the `_nx…` part
/// and the extension (`getfem_v0_b0.5_g0.5_m0`), so that the runs of one configuration at
/// several NX form one series.
pub fn label(path: &Path) -> String {
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    name.trim_end_matches(".json.gz")
        .split('_')
        .filter(|part| !part.starts_with("nx"))
        .collect::<Vec<_>>()
        .join("_")
}

/// The contact trace of the demo's run `run`, read from `path`: its time points, its contact
/// displacement `store_u0`, stress `store_s0` (as `lambda`, at the same times, as the demo
/// stores it) and energy `store_E`, on the Dirichlet scene's mesh with the run's NX; `None`
/// when a value is not finite (the format refuses it: the demo's blown-up Nitsche run).
pub fn contact_trace(path: &Path, run: &DemoRun) -> Option<ExternalRun> {
    let series = &run.series;
    let columns = [&series.u0, &series.s0, &run.energy];
    if columns.iter().any(|c| c.iter().any(|v| !v.is_finite())) {
        return None;
    }
    let nx = run.config.nx;
    Some(ExternalRun {
        path: path.to_path_buf(),
        origin: SampleOrigin::Json,
        version: Version::One,
        scene: SCENE.to_string(),
        code: Code {
            name: "GetFEM demo_dynamic_contact_1D.py".to_string(),
            version: "5.4.2".to_string(),
        },
        label: label(path),
        scheme: None,
        mass: None,
        contact: None,
        energy_definition: None,
        nodes: (0..=nx).map(|i| i as f64 / nx as f64).collect(),
        time: series.time.clone(),
        displacement: None,
        velocity: None,
        lambda: Some(series.s0.iter().copied().map(Some).collect()),
        lambda_time: None,
        contact_displacement: Some(series.u0.clone()),
        energy: Some(run.energy.clone()),
        energy_time: None,
    })
}

/// The contact trace of the demo's run `run` (read from `path`) as version 2 of the format
/// says what it is: the scheme, mass and contact treatment the demo ran (as the harness names
/// them, [`crate::harness::getfem::DemoConfig::scheme`], its `mass_variant` and `contact`); no
/// stress at `t = 0`, which the demo does not compute (it stores 0 there); Paoli–Schatzman's
/// stress at `t_{n−1}` (the demo stores the stress of the step that produced `U^n` with it,
/// `t_0` at the first two samples); the demo's energy `(VᵀMV + UᵀKU)/2` at the sample declared
/// `total-at-sample`, or `total-with-contact-term` with penalty and Nitsche. `None` as
/// [`contact_trace`].
pub fn declared_trace(path: &Path, run: &DemoRun) -> Result<Option<ExternalRun>, Error> {
    let Some(mut trace) = contact_trace(path, run) else {
        return Ok(None);
    };
    let config = &run.config;
    trace.version = Version::Two;
    trace.scheme = Some(config.scheme());
    trace.mass = Some(config.mass_variant());
    trace.contact = Some(config.contact()?.name());
    if let Some(lambda) = trace.lambda.as_mut().and_then(|l| l.first_mut()) {
        *lambda = None;
    }
    if config.version == DemoVersion::PaoliSchatzman {
        let time = &trace.time;
        trace.lambda_time = Some((0..time.len()).map(|n| time[n.max(1) - 1]).collect());
    }
    trace.energy_definition = Some(match config.version {
        DemoVersion::Penalty | DemoVersion::Nitsche => EnergyDefinition::TotalWithContactTerm,
        _ => EnergyDefinition::TotalAtSample,
    });
    Ok(Some(trace))
}

/// The harness's [`TRACE_NORMS`] of a contact trace, as `signorini verify` computes them from
/// a version 1 file of it ([`contact_trace`]): checked against the Dirichlet scene under `root` (to the trace's
/// horizon), then replayed against its exact solution.
pub fn trace_norms(root: &Path, trace: &ExternalRun) -> Result<BTreeMap<Norm, f64>, Error> {
    let horizon = trace.time.last().copied().unwrap_or(0.0);
    let problem = dirichlet(root, horizon)?;
    let mut trace = trace.clone();
    trace
        .check_against(SCENE, &problem)
        .map_err(|e| DemoRunError::Field {
            path: trace.path.clone(),
            field: "arrays".to_string(),
            found: e.to_string(),
            expected: format!("a contact trace of the scene {SCENE}"),
        })?;
    let bar = problem.bar(trace.nx())?;
    let norms: BTreeSet<Norm> = TRACE_NORMS.into_iter().collect();
    let energy = EnergySource::Reported;
    Ok(replay(&trace, &bar, problem.exact.as_ref(), &norms, energy)?.errors)
}

/// The declared contact trace as the CSV form of the format's version 2: an empty `lambda`
/// cell where the stress is not computed, a `lambda_time` column when the trace has one.
fn trace_csv(trace: &ExternalRun) -> String {
    let nodes: Vec<String> = trace.nodes.iter().map(|x| format!("{x:?}")).collect();
    let mut csv = format!(
        "# format: {FORMAT_2}\n# scene: {}\n# code.name: {}\n# code.version: {}\n# label: {}\n",
        trace.scene, trace.code.name, trace.code.version, trace.label,
    );
    let declared = [
        ("scheme", trace.scheme.map(|s| s.name())),
        ("mass", trace.mass.map(|m| m.name().to_string())),
        ("contact", trace.contact.clone()),
        (
            "energy_definition",
            trace.energy_definition.map(|d| d.name().to_string()),
        ),
    ];
    for (key, value) in declared {
        if let Some(value) = value {
            let _ = writeln!(csv, "# {key}: {value}");
        }
    }
    let lambda_time = trace.lambda_time.as_deref();
    let _ = writeln!(
        csv,
        "# mesh.nodes: {}\ntime,contact_displacement,lambda,{}energy",
        nodes.join(", "),
        if lambda_time.is_some() {
            "lambda_time,"
        } else {
            ""
        }
    );
    let (u0, energy) = (
        trace.contact_displacement.as_deref().unwrap_or_default(),
        trace.energy.as_deref().unwrap_or_default(),
    );
    for (n, t) in trace.time.iter().enumerate() {
        let lambda = trace
            .lambda_at(n)
            .map_or_else(String::new, |l| format!("{l:?}"));
        let at = lambda_time.map_or_else(String::new, |times| format!("{:?},", times[n]));
        let _ = writeln!(csv, "{t:?},{:?},{lambda},{at}{:?}", u0[n], energy[n]);
    }
    csv
}

/// Writes the declared contact trace of each run of `runs` whose series are finite
/// ([`declared_trace`]) as a CSV run file into `dir`, named after the run (`….csv`); runs of
/// one configuration at several NX share a [`label`], so that `signorini verify` fits their
/// rates. Returns the files written.
pub fn export_runs(runs: &Path, dir: &Path, limits: &Limits) -> Result<Vec<PathBuf>, Error> {
    let mut written = Vec::new();
    for file in list_runs(runs)? {
        let run = read_run(&file.path)?;
        Estimate::default()
            .writing(written.len() as f64 + 1.0)
            .check(limits)?;
        let Some(trace) = declared_trace(&file.path, &run)? else {
            continue;
        };
        let name = file
            .path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let path = dir.join(format!("{}.csv", name.trim_end_matches(".json.gz")));
        write_atomic(&path, trace_csv(&trace).as_bytes())?;
        written.push(path);
    }
    Ok(written)
}
