//! `reports/getfem.md`: every demo run solved again, checked against its class
//! ([`ClassCheck`]) and compared step by step, the harness's Tables 1–2 norms of GetFEM's runs
//! with their rates, the round-off-chaotic runs against the harness's ensemble, and the demo's
//! own norms beside the same norms computed with its conventions; `reports/getfem.json`: every
//! run's class checks and, for a chaotic run, its timing and norms against the ensemble.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::{
    beyond, ensemble_agreement, initial_data_horizon, label, reproduce, ClassCheck,
    EnsembleAgreement, Expectation, NormInEnsemble, Reproduction, Timing, AMPLITUDE_DECADES,
    DEMO_BLOWN_UP_ENERGY, GETFEM_ENSEMBLE, HARNESS_ENERGY_CEILING, STATE_TOLERANCE,
    STRESS_TOLERANCE, TRACE_NORMS,
};
use crate::harness::files::artifacts::{write_atomic, write_json};
use crate::harness::getfem::{list_runs, read_run, DemoErrorNorms, DemoRun};
use crate::harness::run::norms::Norm;
use crate::harness::study::budget::{self, Estimate, Limits};
use crate::harness::study::progress;
use crate::harness::study::rates::observed_orders;
use crate::harness::study::sensitivity::{EnsembleConfig, Spread, STEP_EPSILON};
use crate::studies::error::Error;

/// The report's file name.
pub const GETFEM_REPORT: &str = "getfem.md";

/// The report's data file: every run's class checks and ensemble ([`GetfemFile`]).
pub const GETFEM_JSON: &str = "getfem.json";

/// One run of the directory, reproduced and checked against its class.
#[derive(Debug, Clone)]
pub struct CheckedRun {
    /// The run file's name.
    pub name: String,
    /// The reproduction.
    pub reproduction: Reproduction,
    /// Its class's checks.
    pub check: ClassCheck,
}

/// One run of the directory, reproduced.
struct Row {
    /// The run file's name.
    name: String,
    /// Its configuration's label (the name without `_nx…`).
    label: String,
    /// The reproduction.
    reproduction: Reproduction,
    /// The largest relative difference between the demo's printed norms and the same norms of
    /// its stored series ([`crate::harness::getfem::DemoSeries::norms`]).
    stored_series: f64,
    /// The ensemble of a round-off-chaotic run ([`GETFEM_ENSEMBLE`]).
    ensemble: Option<EnsembleAgreement>,
    /// The horizons of its ensembles of amplitude [`AMPLITUDE_DECADES`].
    horizons: Vec<Option<usize>>,
    /// Its class's checks.
    check: ClassCheck,
}

/// Reproduces every run of `runs` (a directory of the demo's `.json.gz` files), runs the
/// harness's round-off ensembles of each round-off-chaotic one ([`GETFEM_ENSEMBLE`], and one per
/// amplitude of [`AMPLITUDE_DECADES`]), checks each against its class ([`ClassCheck`]) and writes
/// `out`/[`GETFEM_REPORT`] and `out`/[`GETFEM_JSON`]. Returns the runs with their checks.
pub fn write_getfem_report(
    root: &Path,
    runs: &Path,
    out: &Path,
    limits: &Limits,
) -> Result<Vec<CheckedRun>, Error> {
    let mut rows = Vec::new();
    let mut total = Estimate::default().writing(1.0);
    let files = list_runs(runs)?;
    let stage = progress::stage("GetFEM's demo runs solved again", files.len(), "runs");
    for file in files {
        let run = read_run(&file.path)?;
        total = total.then(reproduction_cost(&run));
        total.check(limits)?;
        let reproduction = reproduce(root, &file.path, &run)?;
        let recomputed = run.series.norms().named();
        let stored_series = run
            .norms
            .named()
            .iter()
            .zip(recomputed)
            .map(|((_, printed), (_, again))| ((printed - again) / printed).abs())
            .fold(0.0_f64, |m, d| if d.is_nan() { m } else { m.max(d) });
        let chaotic = reproduction.expectation == Expectation::RoundOffChaotic;
        let ensemble = chaotic
            .then(|| ensemble_agreement(root, &run, GETFEM_ENSEMBLE))
            .transpose()?;
        // GETFEM_ENSEMBLE's amplitude is one of the decades: its horizon is the agreement's.
        let mut horizons = Vec::new();
        for amplitude in AMPLITUDE_DECADES.into_iter().filter(|_| chaotic) {
            let config = EnsembleConfig {
                amplitude,
                ..GETFEM_ENSEMBLE
            };
            horizons.push(match &ensemble {
                Some(agreement) if config == GETFEM_ENSEMBLE => agreement.horizon,
                _ => initial_data_horizon(root, &run, config)?,
            });
        }
        let check = ClassCheck::of(&reproduction, ensemble.as_ref());
        rows.push(Row {
            check,
            name: file
                .path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
            label: label(&file.path),
            reproduction,
            stored_series,
            ensemble,
            horizons,
        });
        stage.advance(1);
    }
    drop(stage);
    let mut md = String::new();
    step_by_step(&mut md, &rows);
    harness_norms(&mut md, &rows);
    ensembles(&mut md, &rows);
    demo_norms(&mut md, &rows);
    write_atomic(&out.join(GETFEM_REPORT), md.as_bytes())?;
    write_json(&out.join(GETFEM_JSON), &getfem_file(&rows))?;
    Ok(rows
        .into_iter()
        .map(|r| CheckedRun {
            name: r.name,
            reproduction: r.reproduction,
            check: r.check,
        })
        .collect())
}

/// `getfem.json`: the thresholds of the class checks, the ensemble, and every run's checks.
#[derive(Debug, Serialize)]
pub struct GetfemFile {
    /// The crate version that wrote it.
    pub signorini_version: String,
    /// The thresholds of the class checks (`src/studies/getfem/class_check.rs`).
    pub thresholds: Thresholds,
    /// The ensemble the chaotic runs are judged against ([`GETFEM_ENSEMBLE`]).
    pub ensemble: crate::harness::study::sensitivity::EnsembleConfig,
    /// How many runs miss a check of their class.
    pub outside_class: usize,
    /// Every run, in the directory's order.
    pub runs: Vec<RunRecord>,
}

/// The thresholds of the class checks.
#[derive(Debug, Serialize)]
pub struct Thresholds {
    /// [`STATE_TOLERANCE`].
    pub state: f64,
    /// [`STRESS_TOLERANCE`].
    pub stress: f64,
    /// [`DEMO_BLOWN_UP_ENERGY`].
    pub demo_blown_up_energy: f64,
    /// [`HARNESS_ENERGY_CEILING`].
    pub harness_energy_ceiling: f64,
}

/// One run in `getfem.json`.
#[derive(Debug, Serialize)]
pub struct RunRecord {
    /// The run file's name.
    pub run: String,
    /// Whether it holds every check of its class.
    pub within_class: bool,
    /// Its class and checks.
    #[serde(flatten)]
    pub check: ClassCheck,
    /// Every missed check, as `getfem.md` prints it.
    pub misses: Vec<String>,
    /// A chaotic run against the ensemble.
    pub ensemble: Option<EnsembleRecord>,
}

/// A chaotic run against the ensemble in `getfem.json`.
#[derive(Debug, Serialize)]
pub struct EnsembleRecord {
    /// The first step where an initial-data member parts (`null`: none).
    pub horizon: Option<usize>,
    /// The same for the per-step members.
    pub step_horizon: Option<usize>,
    /// The first step where GetFEM's run parts (`null`: never).
    pub getfem_parting: Option<usize>,
    /// Whether GetFEM parts no earlier than the ensemble's first member.
    pub in_time: bool,
    /// How many steps before the ensemble's first member GetFEM parts (0 in time).
    pub steps_early: usize,
    /// `agrees`, `undecided` or `disagrees`.
    pub judgement: &'static str,
    /// Every norm both codes report alike.
    pub norms: Vec<NormRecord>,
}

/// One norm of a chaotic run against the whole ensemble.
#[derive(Debug, Serialize)]
pub struct NormRecord {
    /// The demo's name of the norm.
    pub name: &'static str,
    /// GetFEM's value.
    pub getfem: f64,
    /// The whole ensemble's minimum, median and maximum.
    pub ensemble: Spread,
    /// Whether GetFEM's value lies in `[min, max]`.
    pub inside: bool,
    /// How far outside `[min, max]` it lies (0 inside).
    pub beyond: f64,
    /// That distance in widths `max − min` of the range.
    pub beyond_widths: f64,
}

fn getfem_file(rows: &[Row]) -> GetfemFile {
    let runs: Vec<RunRecord> = rows
        .iter()
        .map(|row| RunRecord {
            run: row.name.clone(),
            within_class: row.check.within(),
            check: row.check.clone(),
            misses: row.check.misses().map(|c| c.text()).collect(),
            ensemble: row.ensemble.as_ref().map(|e| {
                let steps_early = match e.in_time() {
                    Timing::InTime => 0,
                    Timing::Early(n) => n,
                };
                EnsembleRecord {
                    horizon: e.horizon,
                    step_horizon: e.step_horizon,
                    getfem_parting: e.getfem_parting,
                    in_time: e.in_time() == Timing::InTime,
                    steps_early,
                    judgement: e.judgement().name(),
                    norms: e
                        .norms
                        .iter()
                        .map(|n| {
                            let (beyond, beyond_widths) = beyond(n);
                            NormRecord {
                                name: n.name,
                                getfem: n.getfem,
                                ensemble: n.spread,
                                inside: n.inside(),
                                beyond,
                                beyond_widths,
                            }
                        })
                        .collect(),
                }
            }),
        })
        .collect();
    GetfemFile {
        signorini_version: env!("CARGO_PKG_VERSION").to_string(),
        thresholds: Thresholds {
            state: STATE_TOLERANCE,
            stress: STRESS_TOLERANCE,
            demo_blown_up_energy: DEMO_BLOWN_UP_ENERGY,
            harness_energy_ceiling: HARNESS_ENERGY_CEILING,
        },
        ensemble: GETFEM_ENSEMBLE,
        outside_class: runs.iter().filter(|r| !r.within_class).count(),
        runs,
    }
}

/// What reproducing `run` costs: the run with the demo's series and the harness's trace beside
/// it (about twenty values per step), and, should it be chaotic, the members of the ensemble at
/// every amplitude of the sweep and its members perturbed at every step.
pub fn reproduction_cost(run: &DemoRun) -> Estimate {
    let dofs = run.config.nx as f64 + 1.0;
    let steps = run.series.time.len().saturating_sub(1) as f64;
    let one = budget::bar_run_with_histories(dofs, steps, 20.0);
    let runs = 1.0 + (GETFEM_ENSEMBLE.members * (AMPLITUDE_DECADES.len() + 1)) as f64;
    Estimate {
        dof_steps: one.dof_steps * runs,
        ..one
    }
}

/// The largest differences from the demo and the class check, run by run.
fn step_by_step(md: &mut String, rows: &[Row]) {
    let outside: Vec<String> = rows
        .iter()
        .filter(|r| !r.check.within())
        .map(|r| format!("`{}`", r.name))
        .collect();
    let summary = if outside.is_empty() {
        format!("All {} runs are within their class.", rows.len())
    } else {
        format!(
            "**{} of {} runs are outside their class**: {}.",
            outside.len(),
            rows.len(),
            outside.join(", ")
        )
    };
    let _ = write!(
        md,
        "# GetFEM's demo solved again by the harness\n\n\
         Every run of `demo_dynamic_contact_1D.py` in the directory given (by default \
         `tests/data/getfem/`, see its README) solved with the demo's discrete problem: its mass \
         (`getfem-redistributed`, `getfem-singular`, `standard`, `lumped`), contact treatment and \
         time step, with `--conventions getfem-demo`. `Δu` is the largest difference of the \
         contact node's displacement over all steps, `ΔE` of the energy in the demo's definition, \
         `Δs/max|s|` of the contact stress from the first step, `ΔU(T)` of the displacement \
         field at `t = T` (the only field the demo stores) over the nodes; `parts at` is the \
         first step where the displacements differ by more than 1e-8 (`—`: never). What each \
         expectation holds is in `src/studies/getfem/mod.rs` (`Expectation`). `class check`: \
         every run checked against its class with thresholds fixed before these results \
         (docs/src/getfem.md): round-off (`RoundOff`, `UndampedStressRoundOff`): Δu, ΔE and \
         ΔU(T) ≤ {STATE_TOLERANCE:e}, Δs/max|s| ≤ {STRESS_TOLERANCE:e} (up to the first impact \
         for the undamped stress); round-off chaotic: parts after the first impact and, when it \
         parts no earlier than the ensemble's first member, no norm unlike any member (below); \
         demo artefact (`DemoMasslessNitsche`): \
         θ < 0 parts no earlier than the first impact, θ > 0 the demo's energy above \
         {DEMO_BLOWN_UP_ENERGY:e} and the harness's at most {HARNESS_ENERGY_CEILING}; and the \
         harness's run completes. A run that misses one is **outside** its class, with every \
         miss. {summary} Written by `make verify-getfem` (with `getfem.json`).\n\n\
         | run | expectation | Δu (step) | ΔE (step) | Δs/max\\|s\\| (step) | ΔU(T) (node) | parts at | first impact | class check |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for Row {
        name,
        reproduction: r,
        check,
        ..
    } in rows
    {
        let _ = writeln!(
            md,
            "| `{name}` | {:?} | {:.1e} ({}) | {:.1e} ({}) | {:.1e} ({}) | {:.1e} ({}) | {} | {} | {} |",
            r.expectation,
            r.displacement.max,
            r.displacement.step,
            r.energy.max,
            r.energy.step,
            r.stress.max,
            r.stress.step,
            r.final_field.max,
            r.final_field.step,
            r.parting.map_or("—".to_string(), |n| n.to_string()),
            r.first_impact,
            check.text().replace('|', "\\|"),
        );
    }
}

/// Whether the harness's run is GetFEM's to round-off in the whole state, so that its
/// displacement norms are those of GetFEM's run.
fn same_trajectory(r: &Reproduction) -> bool {
    matches!(
        r.expectation,
        Expectation::RoundOff | Expectation::UndampedStressRoundOff
    ) && r.parting.is_none()
}

/// `e` at the finest level and the observed order over the levels, `—` where missing.
fn value_and_rate(levels: &[(f64, Option<f64>)]) -> String {
    let Some((_, Some(finest))) = levels.last() else {
        return "—".to_string();
    };
    let h: Vec<f64> = levels.iter().map(|(h, _)| *h).collect();
    let e: Vec<f64> = levels.iter().map(|(_, e)| e.unwrap_or(f64::NAN)).collect();
    match observed_orders(&h, &e).last().copied().flatten() {
        Some(rate) => format!("{finest:.3e} ({rate:.2})"),
        None => format!("{finest:.3e}"),
    }
}

/// The harness's Tables 1–2 norms of GetFEM's runs, configuration by configuration.
fn harness_norms(md: &mut String, rows: &[Row]) {
    md.push_str(
        "\n## The harness's norms of GetFEM's runs, with their rates\n\n\
         The harness's Tables 1–2 norms (against the engine's exact solution, as in \
         `reports/tables.md`) at the finest NX of each configuration, with the observed order \
         over NX = 20, 40 in brackets. `lambda_L2` and the energy norms are those of GetFEM's own \
         contact trace (`store_s0`, `store_E`), replayed as `signorini verify` replays a version 1 \
         file of it (the stored values as they are, `store_E` in the energy norms; the exported \
         files of `make verify-getfem`, `reports/getfem-verify/`, are version 2: they declare \
         the scheme, mass and contact treatment, leave out the stress at `t = 0`, which the demo \
         does not compute, date Paoli–Schatzman's stress `t_{n−1}`, and show `store_E` beside \
         the norms as the code's own energy); beside them, after \
         the slash, those of the harness's run of the same configuration, which differ where the \
         two codes define or store the quantity differently: the stress at `t = 0` with a \
         massless contact node (the demo stores 0), Paoli–Schatzman's stress (stored with the \
         next step's displacement); the energy wherever the demo's definition is not the \
         harness's (Paoli–Schatzman's and the explicit scheme's velocities, Nitsche's contact \
         term, and with Paoli–Schatzman and a massless contact node the undamped `(−1)ⁿ` mode \
         that the demo's `M·V` bookkeeping carries, which makes its energy grow: the negative \
         rates). The demo stores no displacement field but the final one, so the four `u_*` norms are \
         those of the harness's run, shown only where that run is GetFEM's to round-off at \
         every step and at `t = T` (expectations `RoundOff` and `UndampedStressRoundOff`); `—` \
         where the runs part, or where GetFEM's run is not finite.\n\n| configuration |",
    );
    for norm in Norm::ALL {
        let _ = write!(md, " {} |", norm.key());
    }
    md.push_str("\n|---|");
    md.push_str(&"---|".repeat(Norm::ALL.len()));
    md.push('\n');
    let mut labels: Vec<&str> = rows.iter().map(|r| r.label.as_str()).collect();
    labels.dedup();
    for label in labels {
        let mut series: Vec<&Reproduction> = rows
            .iter()
            .filter(|r| r.label == label)
            .map(|r| &r.reproduction)
            .collect();
        series.sort_by_key(|r| r.config.nx);
        let h = |r: &Reproduction| 1.0 / r.config.nx as f64;
        let _ = write!(md, "| `{label}` |");
        for norm in Norm::ALL {
            let harness: Vec<(f64, Option<f64>)> = series
                .iter()
                .map(|r| (h(r), r.harness_norms.get(&norm).copied()))
                .collect();
            let cell = if !TRACE_NORMS.contains(&norm) {
                if series.iter().all(|r| same_trajectory(r)) {
                    value_and_rate(&harness)
                } else {
                    "—".to_string()
                }
            } else {
                let getfem: Vec<(f64, Option<f64>)> = series
                    .iter()
                    .map(|r| {
                        let e = r.getfem_trace_norms.as_ref().and_then(|n| n.get(&norm));
                        (h(r), e.copied())
                    })
                    .collect();
                format!("{} / {}", value_and_rate(&getfem), value_and_rate(&harness))
            };
            let _ = write!(md, " {cell} |");
        }
        md.push('\n');
    }
}

/// `[min, max]` of a spread.
fn range(s: &Spread) -> String {
    format!("[{:.4e}, {:.4e}]", s.min, s.max)
}

/// `yes`/`no`.
fn yes(inside: bool) -> &'static str {
    if inside {
        "yes"
    } else {
        "no"
    }
}

/// The round-off-chaotic runs against the harness's ensemble: the timing, then each norm
/// before and after the per-step members.
fn ensembles(md: &mut String, rows: &[Row]) {
    let Some(config) = rows.iter().find_map(|r| r.ensemble.as_ref()) else {
        return;
    };
    let decades: Vec<String> = AMPLITUDE_DECADES
        .iter()
        .map(|a| format!("{a:.0e}"))
        .collect();
    let _ = write!(
        md,
        "\n## Round-off-chaotic runs against the harness's ensemble\n\n\
         After its predictability horizon a round-off-chaotic run (`sensitivity.md`) is not reproducible \
         step by step, by GetFEM's own two linear solvers either: there GetFEM's run is measured \
         as one more member of a harness ensemble, and judged against the ensemble's range, \
         never against the harness's one unperturbed run. The ensemble is the unperturbed run, \
         {k} members whose initial displacement carries seeded noise of relative size `A` (as \
         `signorini sensitivity`'s) and {k} members whose carried state (displacement, velocity, \
         acceleration; Paoli–Schatzman's new level) moves after every step by a seeded relative \
         amount in ±ε, ε = {eps:.3e}, the unit round-off (`StepPerturbation`: the rule and why). \
         The horizon of a set is the first step where one of its members parts from the \
         unperturbed run by more than 1e-8. The ensemble is fixed before the comparison: it is \
         `sensitivity.md`'s, `A` = {a:.0e} (`EnsembleConfig::default`), with nothing chosen \
         after seeing GetFEM's runs. **Timing rule**: GetFEM, one more member, is *in time* \
         when it parts no earlier than the ensemble's first member (of either set); where it \
         parts earlier the ensemble does not cover GetFEM's round-off, and the row says by how \
         many steps. `horizons` gives the initial-data set's horizon for `A` = {decades}: where \
         GetFEM's step falls among them measures the size of initial noise the two codes' \
         round-off acts like (a measurement, not a verdict). `Δu` is GetFEM's largest \
         difference up to the initial-data horizon at {a:.0e}.\n\n\
         | run | horizons | GetFEM parts | first impact | horizon at {a:.0e} | horizon per step | timing | Δu to it | judgement |\n\
         |---|---|---|---|---|---|---|---|---|\n",
        k = config.ensemble.members,
        eps = STEP_EPSILON,
        decades = decades.join(", "),
        a = config.ensemble.amplitude,
    );
    let step = |s: Option<usize>| s.map_or("—".to_string(), |n| n.to_string());
    for row in rows {
        let Some(e) = &row.ensemble else { continue };
        let horizons: Vec<String> = row.horizons.iter().map(|&h| step(h)).collect();
        let timing = match e.in_time() {
            Timing::InTime => "in time".to_string(),
            Timing::Early(n) => format!("**{n} steps early**"),
        };
        let _ = writeln!(
            md,
            "| `{}` | {} | {} | {} | {} | {} | {timing} | {:.1e} | {} |",
            row.name,
            horizons.join(", "),
            step(e.getfem_parting),
            e.first_impact,
            step(e.horizon),
            step(e.step_horizon),
            e.before_horizon.max,
            e.judgement().name()
        );
    }
    md.push_str(
        "\nEach demo norm that the two codes report alike: GetFEM's value; the range [min, max] \
         of the ensemble before the per-step members (the unperturbed run and the initial-data \
         members) and its width; the range of the whole ensemble and its width; whether GetFEM's \
         value is inside each, and where it is not, how far outside the whole ensemble's range \
         it lies (and in widths of that range). A run *agrees* when it is in time and every \
         norm is inside the whole ensemble's range; it *disagrees* (a miss of its class) when \
         it parts at or before the first impact, or when it is in time and some norm is unlike \
         any member, `|GetFEM − median| > max − min`; it is *undecided* otherwise: it parts \
         early (GetFEM's round-off acts like a larger perturbation than the ensemble's, whose \
         range then is not GetFEM's distribution), or some norm is outside the range but not \
         unlike the members; the ensemble does not cover it, no verdict either way.\n\n\
         | run | norm | GetFEM | initial data [min, max] | width | inside | with per-step members [min, max] | width | inside | outside by (widths) |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for row in rows {
        let Some(e) = &row.ensemble else { continue };
        for n in &e.norms {
            let NormInEnsemble {
                name,
                getfem,
                initial_data,
                spread,
            } = n;
            let outside = if n.inside() {
                "—".to_string()
            } else {
                let (d, widths) = beyond(n);
                format!("{d:.2e} ({widths:.2})")
            };
            let _ = writeln!(
                md,
                "| `{}` | {name} | {getfem:.4e} | {} | {:.3e} | {} | {} | {:.3e} | {} | {outside} |",
                row.name,
                range(initial_data),
                initial_data.range(),
                yes(n.inside_initial_data()),
                range(spread),
                spread.range(),
                yes(n.inside()),
            );
        }
    }
    coverage(md, rows);
}

/// Whether the ensembles cover GetFEM's chaotic runs: in time, and in every norm, with what
/// they do not cover.
fn coverage(md: &mut String, rows: &[Row]) {
    let chaotic: Vec<(&str, &EnsembleAgreement)> = rows
        .iter()
        .filter_map(|r| Some((r.name.as_str(), r.ensemble.as_ref()?)))
        .collect();
    let in_time = chaotic
        .iter()
        .filter(|(_, e)| e.in_time() == Timing::InTime)
        .count();
    let covered = chaotic
        .iter()
        .filter(|(_, e)| e.norms.iter().all(NormInEnsemble::inside))
        .count();
    let _ = write!(
        md,
        "\nCoverage: GetFEM parts in time in {in_time} of {n} chaotic runs, and the whole \
         ensemble's range holds GetFEM's value in every norm in {covered} of {n}.",
        n = chaotic.len()
    );
    let misses: Vec<String> = chaotic
        .iter()
        .flat_map(|(name, e)| {
            e.norms.iter().filter(|n| !n.inside()).map(move |n| {
                let (d, widths) = beyond(n);
                format!("`{name}` {} by {d:.2e} ({widths:.2} widths)", n.name)
            })
        })
        .collect();
    if misses.is_empty() {
        md.push('\n');
    } else {
        let _ = writeln!(md, " Outside: {}.", misses.join("; "));
    }
}

/// The demo's norms beside the same norms of its stored series and of the harness's run.
fn demo_norms(md: &mut String, rows: &[Row]) {
    md.push_str(
        "\n## The demo's norms and the same norms of the harness's run\n\n\
         The demo's seven relative error norms as it prints them, and the harness's run measured \
         the same way (`DemoNorms`: nodal interpolant, rectangle sums). `stored Δ` is the largest \
         relative difference between the printed norms and the same norms recomputed by the \
         harness from the demo's stored series (`DemoSeries::norms`): the demo's conventions, \
         reproduced. Where the runs agree, the displacement norms agree to the printed digits. \
         Three reporting conventions, not the solutions, separate the others: \
         (1) the velocity of a massless contact node (masses 1, 2 with the implicit schemes), \
         which the dynamics leave undefined: the demo reports `(U¹₀ − U⁰₀)/Δt`, the harness the \
         value of Newmark's recurrences, so `LinfL2v` and `L2L2v` differ; (2) Paoli–Schatzman's \
         velocity, which the harness reports at `t_{n−½}` (`(Uⁿ − Uⁿ⁻¹)/Δt`) and the demo at \
         `t_n`; (3) the stress at `t = 0`, which the demo stores as 0 while the harness's implicit \
         start reports `λ⁰ = −½` (the exact `u_x(0, 0)`), so `L2sn` differs with masses 1 and 2. \
         Where the runs part (round-off chaos, the demo's massless Nitsche) the norms differ as \
         the runs do.\n\n| run | stored Δ |",
    );
    for name in DemoErrorNorms::NAMES {
        let _ = write!(md, " {name} demo / harness |");
    }
    md.push_str("\n|---|---|");
    md.push_str(&"---|".repeat(DemoErrorNorms::NAMES.len()));
    md.push('\n');
    for row in rows {
        let r = &row.reproduction;
        let _ = write!(md, "| `{}` | {:.1e} |", row.name, row.stored_series);
        for ((_, d), (_, h)) in r
            .demo_norms
            .named()
            .into_iter()
            .zip(r.harness_demo_norms.named())
        {
            let _ = write!(md, " {d:.6e} / {h:.6e} |");
        }
        md.push('\n');
    }
}
