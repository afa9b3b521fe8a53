//! The figures of the papers and of the harness, drawn from the data `make report` and
//! `make stability` write under `reports/` (never recomputed here).
//!
//! | file | from | what |
//! |---|---|---|
//! | `contact-<scheme>.svg` | `data/histories/<scheme>.json` | 1D paper Figures 7, 11, 13, 15, 17, 19, 21 |
//! | `energy-<scheme>.svg` | same | Figures 8, 12, 14, 16, 18, 20, 22 |
//! | `convergence-<scheme>-<norm>.svg` | `rates.json`, `sensitivity.json` | Figures 9–10 (every scheme; chaotic cases as ensemble median and min–max band) |
//! | `gravity-points-<mass>.svg`, `gravity-convergence-<mass>.svg`, `gravity-strain-<mass>.svg` | `gravity/` | Figures 2, 3, 4 |
//! | `work-precision.svg` | `work-precision.json` | error against wall time |
//! | `stability-<mass>.svg`, `stability-rivals-<mass>.svg` | `stability.json` | energy histories of the long horizon |

use std::path::Path;

use super::convergence::{convergence_figures, convergence_series, panel_label};
use super::elastic::{elastic_convergence_figures, elastic_figures};
use crate::harness::files::artifacts::{read_json, write_atomic};
use crate::harness::files::error as files;
use crate::harness::files::input::REPORT_DATA;
use crate::harness::problem::{MassVariant, Scheme};
use crate::harness::reference::fine_mesh::ElasticHistories;
use crate::harness::render::figures::{
    contact_node_figure, convergence_figure, energy_figure, line_figure, time_series_figure,
    work_precision_figure, Colouring, ContactAxes, ContactPanel, ConvergenceFit, EnergyPanel,
    Figure, FigureError, WorkPrecisionSeries,
};
use crate::harness::run::norms::Norm;
use crate::harness::run::BarRun;
use crate::harness::study::sensitivity::Sensitivity;
use crate::harness::study::Study;
use crate::studies::cost::{WorkPrecision, WorkPrecisionFile, WORK_PRECISION_JSON};
use crate::studies::elastic_study::{files as elastic_files, ElasticStudy};
use crate::studies::error::Error;
use crate::studies::gravity;
use crate::studies::histories::{SchemeHistories, HISTORIES_DIR};
use crate::studies::stability::{StabilityRecord, Verdict, STABILITY_JSON};
use crate::studies::tables::{RatesFile, RATES_JSON, SENSITIVITY_JSON};

/// The directory of the figures, under a reports directory.
pub const FIGURES_DIR: &str = "figures";

/// The levels of `runs` as a title says them: `NX = 10, 20, 40`.
fn levels_of(runs: &[(MassVariant, usize, BarRun)]) -> String {
    let mut nx: Vec<usize> = runs.iter().map(|r| r.1).collect();
    nx.sort_unstable();
    nx.dedup();
    let nx: Vec<String> = nx.iter().map(|n| n.to_string()).collect();
    format!("NX = {}", nx.join(", "))
}

/// The caption of a contact figure's redistributed-mass panel: its runs start at `u_h(0, 0) =
/// u⁰(Δx) = ½ − Δx/2` (0.45 at NX = 10), not at the exact ½, because the redistributed mass
/// puts no mass on the contact node, whose displacement then follows statically from its
/// neighbour's (the massless contact node). Short enough to stay inside its panel.
const REDISTRIBUTED_START: &str = "u_h(0, 0) = u⁰(Δx)";

/// The contact-node and energy figures of one scheme (standard mass left, redistributed right).
pub fn scheme_figures(h: &SchemeHistories) -> Result<Vec<Figure>, FigureError> {
    let mut contact = Vec::new();
    let mut energy = Vec::new();
    for mass in MassVariant::PAPER {
        let runs = h.runs.iter().filter(|r| r.0 == mass);
        contact.push(ContactPanel {
            label: if mass == MassVariant::Redistributed {
                format!("{}, {REDISTRIBUTED_START}", panel_label(mass))
            } else {
                panel_label(mass)
            },
            runs: runs
                .clone()
                .filter_map(|(_, nx, r)| {
                    r.observed
                        .contact_history
                        .clone()
                        .map(|c| (format!("NX = {nx}"), c))
                })
                .collect(),
        });
        energy.push(EnergyPanel {
            label: panel_label(mass),
            runs: runs
                .filter_map(|(_, nx, r)| {
                    r.observed
                        .energy_history
                        .clone()
                        .map(|e| (format!("NX = {nx}"), e))
                })
                .collect(),
        });
    }
    let title = |what: &str| {
        format!(
            "1D bar, {}, {}, standard (left) and redistributed (right) mass: {what}",
            h.label,
            levels_of(&h.runs)
        )
    };
    Ok(vec![
        (
            format!("contact-{}.svg", h.scheme),
            contact_node_figure(
                &title("contact node u(0, t) and λ(t)"),
                ContactAxes {
                    displacement: "u(0, t)",
                    multiplier: "λ(t)",
                },
                &contact,
            )?,
        ),
        (
            format!("energy-{}.svg", h.scheme),
            energy_figure(&title("energy"), &energy)?,
        ),
    ])
}

/// The gravity benchmark's Figures 2–4 from its study, its round-off sensitivity (a chaotic
/// case is drawn as its ensemble, as in [`convergence_figures`]) and its runs at
/// [`gravity::FIGURE_LEVEL`] (one per mass, of the study's first scheme). In Figures 2 and 4 a
/// computed curve and its exact counterpart share a colour, the computed one solid with
/// markers, the exact one dashed over it.
///
/// Errors: `Inconsistent` when `sensitivity` was run at other levels, ratio or horizon than
/// `study`, or lacks a norm's errors for a chaotic case; the errors of the figures.
pub fn gravity_figures(
    study: &Study,
    sensitivity: Option<&Sensitivity>,
    runs: &[(MassVariant, BarRun)],
) -> Result<Vec<Figure>, FigureError> {
    if let Some(s) = sensitivity {
        if s.config != study.config {
            return Err(FigureError::Inconsistent {
                what: format!(
                    "the gravity sensitivity study ran with {:?}, the gravity study with {:?}",
                    s.config, study.config
                ),
            });
        }
    }
    let mut out = Vec::new();
    let scheme = study
        .cases
        .first()
        .map_or(String::new(), |c| c.case.scheme.label());
    let title = |mass: MassVariant, what: &str| {
        format!(
            "Gravity, {scheme}, NX = {}, {}: {what}",
            gravity::FIGURE_LEVEL,
            panel_label(mass)
        )
    };
    for (mass, r) in runs {
        if let Some(p) = &r.observed.point_history {
            let mut series = Vec::new();
            for (k, x) in p.x.iter().enumerate() {
                series.push((
                    format!("u_h(x = {x})"),
                    p.time.clone(),
                    p.displacement[k].clone(),
                ));
                series.push((
                    format!("u(x = {x}), exact"),
                    p.time.clone(),
                    p.displacement_exact[k].clone(),
                ));
            }
            out.push((
                format!("gravity-points-{}.svg", mass.name()),
                line_figure(
                    &title(*mass, "displacement at points (Figure 2)"),
                    ("t", "u"),
                    &series,
                    Colouring::ComputedAndExact,
                )?,
            ));
        }
        let mut strain = Vec::new();
        for f in &r.observed.fields {
            strain.push((
                format!("∂x u_h, t = {:.2}", f.time),
                f.x_mid.clone(),
                f.strain.clone(),
            ));
            strain.push((
                format!("∂x u, t = {:.2}, exact", f.time),
                f.x_mid.clone(),
                f.strain_exact.clone(),
            ));
        }
        if !strain.is_empty() {
            out.push((
                format!("gravity-strain-{}.svg", mass.name()),
                line_figure(
                    &title(*mass, "strain along the bar (Figure 4)"),
                    ("x", "∂x u"),
                    &strain,
                    Colouring::ComputedAndExact,
                )?,
            ));
        }
    }
    // Figure 3 is the paper's Crank–Nicolson; the rivals' rates are in `gravity.md`.
    let figured = study
        .cases
        .iter()
        .filter(|c| c.case.scheme == Scheme::CRANK_NICOLSON);
    for c in figured {
        let chaotic = sensitivity
            .and_then(|s| s.case(&c.case.id()))
            .filter(|e| e.chaotic);
        let mut series = Vec::new();
        for norm in [
            Norm::DisplacementLinfH,
            Norm::DisplacementL2H,
            Norm::DisplacementLinfV,
            Norm::DisplacementL2V,
        ] {
            series.extend(convergence_series(c, norm, chaotic, norm.key())?);
        }
        out.push((
            format!("gravity-convergence-{}.svg", c.case.mass.name()),
            convergence_figure(
                &format!(
                    "Gravity, {}, {}: errors ‖u_h − u‖ in H and V (Figure 3)",
                    c.case.scheme.label(),
                    panel_label(c.case.mass)
                ),
                &series,
                &ConvergenceFit::Exact,
            )?,
        ));
    }
    Ok(out)
}

/// Error in `L∞(0,T;H)` against wall time, one curve per case (a colour and marker per scheme,
/// solid for the standard mass and dashed for the redistributed one): the paper's cases in
/// `work-precision.svg`, the rivals' (when the data hold them) in `work-precision-rivals.svg`.
pub fn work_precision_figures(data: &[WorkPrecision]) -> Result<Vec<Figure>, FigureError> {
    let series = |paper: bool| -> Vec<(String, String, WorkPrecisionSeries)> {
        data.iter()
            .filter(|w| w.norm == Norm::DisplacementLinfH && in_the_paper(&w.case) == paper)
            .map(|w| {
                let (scheme, mass) = w.case.split_once('/').unwrap_or((&w.case, ""));
                let label = match scheme.parse::<Scheme>() {
                    Ok(s) => format!("{}, {mass}", s.label()),
                    Err(_) => w.case.clone(),
                };
                (
                    scheme.to_owned(),
                    mass.to_owned(),
                    WorkPrecisionSeries {
                        label,
                        seconds: w.seconds.clone(),
                        errors: w.errors.clone(),
                    },
                )
            })
            .collect()
    };
    let title = |who: &str, cases: usize| {
        format!(
            "Work–precision, {who} ({cases} cases, scheme × mass): ‖u_h − u‖ L∞(0,T;H) against \
             wall time"
        )
    };
    let paper = series(true);
    let mut out = vec![(
        "work-precision.svg".to_string(),
        work_precision_figure(&title("the paper's schemes", paper.len()), &paper)?,
    )];
    let rivals = series(false);
    if !rivals.is_empty() {
        out.push((
            "work-precision-rivals.svg".to_string(),
            work_precision_figure(&title("the rivals", rivals.len()), &rivals)?,
        ));
    }
    Ok(out)
}

/// Whether a case id `scheme/mass` names one of the paper's schemes (not a rival).
fn in_the_paper(case: &str) -> bool {
    case.split('/')
        .next()
        .and_then(|name| name.parse::<Scheme>().ok())
        .is_some_and(|s| Scheme::paper_schemes().contains(&s))
}

/// Elements of the stability suite's long-horizon case (`studies::stability::hard_cases`; a
/// test holds them equal), which its records do not store.
pub const LONG_HORIZON_NX: usize = 80;

/// The long-horizon energy histories, `E/E_0`, one figure per mass for the paper's schemes
/// (`stability-<mass>.svg`) and one per mass for the rivals when the records hold them
/// (`stability-rivals-<mass>.svg`); diverged runs are not drawn and named in the legend. Each
/// curve's legend gives the study's verdict and its largest energy drift `max |E − E₀|/E₀` as a
/// percentage, so that a "stable" run that lost energy says how much.
pub fn stability_figures(records: &[StabilityRecord]) -> Result<Vec<Figure>, FigureError> {
    let mut out = Vec::new();
    for (paper, group, name) in [
        (true, "the paper's schemes, ", ""),
        (false, "the rivals, ", "-rivals"),
    ] {
        for mass in MassVariant::PAPER {
            let mine: Vec<&StabilityRecord> = records
                .iter()
                .filter(|r| {
                    r.hard_case == "long-horizon"
                        && r.case.ends_with(mass.name())
                        && in_the_paper(&r.case) == paper
                })
                .collect();
            if !mine.is_empty() {
                out.push(stability_figure(&mine, mass, group, name)?);
            }
        }
    }
    Ok(out)
}

/// One figure of [`stability_figures`]: the long-horizon records `mine` of one `mass`.
fn stability_figure(
    mine: &[&StabilityRecord],
    mass: MassVariant,
    group: &str,
    name: &str,
) -> Result<Figure, FigureError> {
    let left_out: Vec<&str> = mine
        .iter()
        .filter(|r| r.verdict == Verdict::Diverged)
        .map(|r| r.case.split('/').next().unwrap_or(&r.case))
        .collect();
    let series: Vec<(String, Vec<f64>, Vec<f64>)> = mine
        .iter()
        .filter(|r| r.verdict != Verdict::Diverged && !r.energy_samples.is_empty())
        .map(|r| {
            let e0 = r.energy_samples[0].1;
            (
                format!(
                    "{}: {}, max |E − E₀|/E₀ = {}",
                    r.case.split('/').next().unwrap_or(&r.case),
                    r.verdict.word(),
                    percent(r.max_energy_drift)
                ),
                r.energy_samples.iter().map(|s| s.0).collect(),
                r.energy_samples.iter().map(|s| s.1 / e0).collect(),
            )
        })
        .collect();
    let title = format!(
        "Stability, long horizon (T = 300, NX = {LONG_HORIZON_NX}), {group}{} mass: E/E₀",
        mass.name()
    );
    let notes: Vec<String> = left_out
        .iter()
        .map(|s| format!("{s}: diverged (not drawn)"))
        .collect();
    Ok((
        format!("stability{name}-{}.svg", mass.name()),
        time_series_figure(&title, "E/E₀", &series, &notes)?,
    ))
}

/// A relative drift as a percentage with two significant digits (`15 %`, `0.033 %`), in
/// scientific notation below 10⁻⁴ % (`8.4e-10 %`: a round-off drift is not 0.000000 %).
fn percent(fraction: f64) -> String {
    let p = 100.0 * fraction;
    if p >= 10.0 {
        format!("{p:.0} %")
    } else if p >= 1e-4 {
        let decimals = (1.0 - p.log10().floor()).clamp(1.0, 6.0) as usize;
        format!("{p:.decimals$} %")
    } else {
        format!("{p:.1e} %")
    }
}

/// Why an input of the figures could not be read: a missing file is `make report`'s to write.
fn unreadable(e: &files::Error) -> String {
    match e {
        files::Error::Io { path, .. } if path.ends_with(STABILITY_JSON) => {
            format!("{e} (run `make stability` first)")
        }
        files::Error::Io { .. } => format!("{e} (run `make report` first)"),
        _ => e.to_string(),
    }
}

/// Draws every figure whose data exist under `reports` and writes them to `into/figures/`
/// (`into` is `reports` or where its new files are staged); returns the names written and the
/// inputs that were missing.
pub fn write_figures(reports: &Path, into: &Path) -> Result<(Vec<String>, Vec<String>), Error> {
    let mut figures: Vec<Figure> = Vec::new();
    let mut missing = Vec::new();
    let histories = reports.join(HISTORIES_DIR);
    let mut files: Vec<_> = std::fs::read_dir(&histories)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.sort();
    if files.is_empty() {
        missing.push(histories.display().to_string());
    }
    for f in files {
        figures.extend(scheme_figures(&read_json::<SchemeHistories>(
            &f,
            REPORT_DATA,
        )?)?);
    }
    let sensitivity_path = reports.join(SENSITIVITY_JSON);
    let sensitivity = if sensitivity_path.exists() {
        Some(read_json::<Sensitivity>(&sensitivity_path, REPORT_DATA)?)
    } else {
        missing.push(format!(
            "{} (run `make report` first; chaotic cases are drawn from their one unperturbed run)",
            sensitivity_path.display()
        ));
        None
    };
    match read_json::<RatesFile>(&reports.join(RATES_JSON), REPORT_DATA) {
        Ok(r) => figures.extend(convergence_figures(&r.study, sensitivity.as_ref())?),
        Err(e) => missing.push(unreadable(&e)),
    }
    let gravity_dir = reports.join(gravity::GRAVITY_DIR);
    let gravity_runs: Result<Vec<(MassVariant, BarRun)>, _> = MassVariant::PAPER
        .iter()
        .map(|&m| {
            read_json::<BarRun>(&gravity_dir.join(gravity::run_file(m)), REPORT_DATA)
                .map(|r| (m, r))
        })
        .collect();
    let gravity_sensitivity = gravity_dir.join(gravity::SENSITIVITY_JSON);
    let gravity_sensitivity = if gravity_sensitivity.exists() {
        Some(read_json::<Sensitivity>(&gravity_sensitivity, REPORT_DATA)?)
    } else {
        None
    };
    match (
        read_json::<Study>(&gravity_dir.join(gravity::STUDY_JSON), REPORT_DATA),
        gravity_runs,
    ) {
        (Ok(study), Ok(runs)) => figures.extend(gravity_figures(
            &study,
            gravity_sensitivity.as_ref(),
            &runs,
        )?),
        (Err(e), _) | (_, Err(e)) => missing.push(unreadable(&e)),
    }
    match read_json::<WorkPrecisionFile>(&reports.join(WORK_PRECISION_JSON), REPORT_DATA) {
        Ok(w) => figures.extend(work_precision_figures(&w.work_precision)?),
        Err(e) => missing.push(unreadable(&e)),
    }
    for d in [2, 3] {
        let study =
            read_json::<ElasticStudy>(&reports.join(elastic_files::study_file(d)), REPORT_DATA);
        let data = read_json::<ElasticHistories>(
            &reports.join(elastic_files::histories_file(d)),
            REPORT_DATA,
        );
        match study {
            Ok(study) => {
                figures.extend(elastic_convergence_figures(&study)?);
                match data {
                    Ok(data) => figures.extend(elastic_figures(&study, &data)?),
                    Err(e) => missing.push(unreadable(&e)),
                }
            }
            Err(e) => missing.push(unreadable(&e)),
        }
    }
    match read_json::<Vec<StabilityRecord>>(&reports.join(STABILITY_JSON), REPORT_DATA) {
        Ok(s) => figures.extend(stability_figures(&s)?),
        Err(e) => missing.push(unreadable(&e)),
    }
    let dir = into.join(FIGURES_DIR);
    let mut names = Vec::new();
    for (name, svg) in figures {
        write_atomic(&dir.join(&name), svg.as_bytes())?;
        names.push(name);
    }
    Ok((names, missing))
}
