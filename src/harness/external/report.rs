//! The markdown of a verification (`verify.md`, and what `signorini verify` prints): Tables
//! 1–2 with one row per series, the norms not computed and why, what the norms leave out, and
//! each series' per-level errors in the harness's own convergence tables, the harness's runs of
//! the files' declared schemes, the displacement errors at the samples of files with fields at
//! some samples only, and the codes' own energies beside the norms.

use std::fmt::Write as _;

use super::verify::{ReportedEnergy, Series, Verification};
use crate::harness::render::report::{convergence_table, table_text};
use crate::harness::run::norms::Norm;
use crate::harness::study::verdicts::{oscillation_ratio_text, oscillation_word};

/// The columns of Table 1 (displacement).
const TABLE1: [Norm; 4] = [
    Norm::DisplacementLinfH,
    Norm::DisplacementL2H,
    Norm::DisplacementLinfV,
    Norm::DisplacementL2V,
];

/// One cell: the rate over all levels, `—` without two levels to fit, or `not computed`.
fn cell(s: &Series, norm: Norm) -> String {
    match s.norm(norm) {
        Some(r) => r.fit.map_or("—".to_string(), |f| format!("{:.2}", f.rate)),
        None => "not computed".to_string(),
    }
}

/// `label | code version`, the label marked when the series does not solve what it declares.
fn row_head(s: &Series) -> String {
    format!(
        "{}{} | {} {}",
        table_text(&s.label),
        differs_mark(s),
        table_text(&s.code.name),
        table_text(&s.code.version)
    )
}

/// ` (**differs from its declared scheme and mass: 6.2e-1**)` when the harness's run of what the
/// series declares parts from its files by more than round-off; empty otherwise.
fn differs_mark(s: &Series) -> String {
    s.differs_from_declared().map_or(String::new(), |d| {
        format!(
            " (**differs from its declared scheme and mass: {:.1e}**)",
            d.largest()
        )
    })
}

/// The whole markdown of `v`: what its errors are measured against, Tables 1–2, the harness's
/// runs of the declared schemes, the displacement errors at sampled steps and the codes' own
/// energies. A verification against a fine-mesh reference (one with a rate-bias bound) measures
/// the box study's errors, which the opening says.
pub fn render<J>(v: &Verification<J>) -> String {
    let mut out = String::new();
    let each_cell = "Each cell: the least-squares rate over the series' levels (`—` with fewer \
                     than two).";
    let against = match &v.rate_bias {
        None => {
            let _ = writeln!(
                out,
                "# Verification of external runs\n\nScene `{}` against the exact solution `{}`, \
                 T = {}. {each_cell}\n",
                v.scene, v.reference, v.horizon
            );
            "the exact energy"
        }
        Some(_) => {
            let _ = writeln!(
                out,
                "# Verification of external runs\n\nScene `{}` against {}, T = {}. {each_cell} \
                 The errors are the box study's: the displacement in H and V against the \
                 reference's projection on the file's level, the total contact force, and the \
                 energy the harness computes from the file's fields with its own mass and \
                 stiffness matrices.\n",
                v.scene, v.reference, v.horizon
            );
            let own_mesh = v
                .series
                .iter()
                .flat_map(|s| &s.runs)
                .any(|r| r.own_mesh.is_some());
            if own_mesh {
                let _ = writeln!(
                    out,
                    "A file on its own mesh (its notes say which) is measured against the \
                     reference's projections on the finest study level instead, by a quadrature \
                     on its cells, with the bound its notes state; its level's `h` is its longest \
                     edge, its `NX` its number of cells; its contact force is the resultant of its \
                     multipliers over its contact face, its notes give the face centre's \
                     displacement and pressure beside the reference's, and its energy is \
                     integrated on its own cells with the mass it declares.\n"
                );
            }
            "the reference's energy"
        }
    };
    out.push_str(&tables(v));
    out.push_str(&step_differences(v));
    out.push_str(&sampled_displacement(v));
    let energies: Vec<&ReportedEnergy> = v
        .series
        .iter()
        .flat_map(|s| &s.reported_energy)
        .chain(&v.reported_energy)
        .collect();
    out.push_str(&reported_energies(&energies, against));
    out
}

/// The harness's own runs of the files' declared schemes and masses beside the files, their
/// largest relative differences; empty when no file declares both.
fn step_differences<J>(v: &Verification<J>) -> String {
    let mut out = String::new();
    let opt = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.1e}"));
    for d in v.series.iter().flat_map(|s| &s.step_differences) {
        if out.is_empty() {
            out.push_str(
                "\n## The harness's run of each file's declared scheme and mass\n\nThe \
                 harness runs the scheme and mass a file declares (with the scene's contact \
                 treatment) on the scene's mesh at the file's level (a box series: at its \
                 coarsest level), from the file's first sample, at its time step. Each cell: the largest difference over the samples, \
                 relative to the harness's largest value (`λ` at the samples where both report \
                 it at the same time). With `u` within round-off (the bound: 10⁻¹⁰ for \
                 double precision, 1000 machine epsilons of the file's numbers when larger) both \
                 codes solve the same discrete problem (`v` and `λ`, recovered from differences \
                 over a step, carry round-off amplified by 1/Δt); beyond it the file does not \
                 solve the scheme and mass it declares: when it is its series' coarsest file, \
                 the series is marked so and the note's findings do not judge it as that case. \
                 The bound is at least 100 times the parting of the harness's own twin run, \
                 started from the file's first sample perturbed by the file's rounding: on a \
                 round-off chaotic case the twin parts by the size of the solution and nothing \
                 is decided.\n\n| file | scheme | samples | u | v | λ | within \
                 round-off |\n|---|---|---|---|---|---|---|\n",
            );
        }
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.1e} | {} | {} | {} |",
            d.file,
            d.scheme,
            d.samples,
            d.displacement,
            opt(d.velocity),
            opt(d.multiplier),
            if d.differs() {
                format!("**no** (bound {:.0e})", d.tolerance)
            } else if d.tolerance >= 1.0 {
                format!(
                    "*undecided*: round-off chaotic (its twin parts by {:.0e})",
                    d.self_parting
                )
            } else {
                format!("yes (bound {:.0e})", d.tolerance)
            }
        );
    }
    out
}

/// The displacement errors at the samples that have fields, of the files that lack them at
/// some samples (their `u` norms are not computed); empty when no file does.
fn sampled_displacement<J>(v: &Verification<J>) -> String {
    let mut out = String::new();
    let runs = v.series.iter().flat_map(|s| &s.runs);
    for r in runs.filter(|r| !r.displacement_at_samples.is_empty()) {
        if out.is_empty() {
            out.push_str(
                "\n## Displacement errors at the samples with fields\n\n| file | t | ‖e‖_H \
                 (L² in space) | ‖e‖_V (H¹) |\n|---|---|---|---|\n",
            );
        }
        for e in &r.displacement_at_samples {
            let _ = writeln!(
                out,
                "| {} | {} | {:.6e} | {:.6e} |",
                r.file, e.time, e.h, e.v
            );
        }
    }
    out
}

/// The codes' own energies `energies` beside the energy norms, their distances to `against`
/// (the exact energy, the reference's); empty when no file reports one.
fn reported_energies(energies: &[&ReportedEnergy], against: &str) -> String {
    let mut out = String::new();
    for e in energies {
        if out.is_empty() {
            let _ = write!(
                out,
                "\n## The codes' own energies (beside the energy norms, never in them)\n\n| file \
                 | definition | L∞ distance to {against} | L² distance |\n|---|---|---|---|\n",
            );
        }
        let definition = serde_json::to_value(e.definition)
            .ok()
            .and_then(|d| d.as_str().map(str::to_string))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "| {} | {definition} | {:.6e} | {:.6e} |",
            e.file, e.linf, e.l2
        );
    }
    out
}

/// Tables 1–2 of the series of `v`, the norms not computed, and each series' per-level errors
/// and observed orders: the body of [`render`].
fn tables<J>(v: &Verification<J>) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "### Table 1: convergence rates for the displacement\n");
    let _ = writeln!(
        out,
        "| Configuration | Code | {} |",
        TABLE1.map(Norm::label).join(" | ")
    );
    let _ = writeln!(out, "|---|---|{}", "---|".repeat(TABLE1.len()));
    for s in &v.series {
        let cells: Vec<String> = TABLE1.iter().map(|&n| cell(s, n)).collect();
        let _ = writeln!(out, "| {} | {} |", row_head(s), cells.join(" | "));
    }
    let _ = writeln!(
        out,
        "\n### Table 2: convergence rates for the Lagrange multiplier and the energy\n"
    );
    let _ = writeln!(
        out,
        "| Configuration | Code | {} | Oscillations (TV ratio) | {} | {} |",
        Norm::MultiplierL2.label(),
        Norm::EnergyLinf.label(),
        Norm::EnergyL2.label()
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|");
    for s in &v.series {
        let osc = s.oscillation_indicator().map_or("—".to_string(), |r| {
            format!("{} ({})", oscillation_word(r), oscillation_ratio_text(r))
        });
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} |",
            row_head(s),
            cell(s, Norm::MultiplierL2),
            osc,
            cell(s, Norm::EnergyLinf),
            cell(s, Norm::EnergyL2)
        );
    }
    let missing: Vec<&Series> = v
        .series
        .iter()
        .filter(|s| !s.not_computed.is_empty())
        .collect();
    if !missing.is_empty() {
        let _ = writeln!(out, "\n### Not computed\n");
        for s in missing {
            for same in s.not_computed.chunk_by(|a, b| a.reason == b.reason) {
                let keys: Vec<String> =
                    same.iter().map(|n| format!("`{}`", n.norm.key())).collect();
                let _ = writeln!(
                    out,
                    "- {}: {} not computed: {}",
                    table_text(&s.label),
                    keys.join(", "),
                    same[0].reason
                );
            }
        }
    }
    let noted: Vec<&Series> = v.series.iter().filter(|s| !s.notes.is_empty()).collect();
    if !noted.is_empty() {
        let _ = writeln!(out, "\n### Notes\n");
        for s in noted {
            for note in &s.notes {
                let _ = writeln!(out, "- {}: {note}", table_text(&s.label));
            }
        }
    }
    let _ = writeln!(out, "\n## Per-level errors and observed orders\n");
    for s in &v.series {
        let heading = format!(
            "{}{} — {} {}",
            table_text(&s.label),
            differs_mark(s),
            table_text(&s.code.name),
            table_text(&s.code.version)
        );
        out.push_str(&convergence_table(&heading, &s.levels, &s.rates));
    }
    out
}
