//! The M^mod rows of Tables 1–2 under both starts (docs/src/starts-and-conventions.md): the
//! tables' study uses the harness's static start; the 1D paper
//! and GetFEM keep the data and take the implicit multiplier `λ⁰ = −(S U⁰)₀`. With a massless
//! contact node the two are different discrete problems; this section measures what the choice
//! moves.

use std::fmt::Write as _;

use crate::harness::problem::{MassVariant, Start};
use crate::harness::run::norms::Norm;
use crate::harness::study::{Case, Study, StudyConfig};

/// `config` with its runs started by the implicit multiplier instead of its own start.
pub fn implicit_start(config: &StudyConfig) -> StudyConfig {
    let mut config = config.clone();
    config.settings.conventions.start = Start::ImplicitMultiplier;
    config
}

/// The cases of `cases` with a massless contact node (the redistributed mass): those whose
/// start the section compares, in their order.
pub fn massless_contact(cases: impl IntoIterator<Item = Case>) -> Vec<Case> {
    cases
        .into_iter()
        .filter(|c| c.mass == MassVariant::Redistributed)
        .collect()
}

/// The section of `tables.md`: each case of `implicit` with its rates under the static start
/// (from `study`) and the implicit-multiplier start, and the largest relative change of an
/// error over the levels and norms.
pub fn starts_section(study: &Study, implicit: &Study) -> String {
    let mut md = String::from(
        "## The M^mod rows under both starts\n\n\
         The tables above start the massless contact node in static equilibrium (`--start \
         static`, the harness's default: `u₀(0)` moved from ½ to `u₀(h)`). The 1D paper and \
         GetFEM keep the data and take the implicit multiplier `λ⁰ = −(S U⁰)₀ = −½` \
         (`--start implicit-multiplier`). Each cell: the rate over all levels under the static \
         / the implicit-multiplier start; `largest error change`: the largest `|e_implicit / \
         e_static − 1|` over the levels and norms, with its norm and NX.\n\n| Scheme | Mass |",
    );
    for norm in &study.norms {
        let _ = write!(md, " {} |", norm.key());
    }
    md.push_str(" largest error change |\n|---|---|");
    md.push_str(&"---|".repeat(study.norms.len() + 1));
    md.push('\n');
    for other in &implicit.cases {
        let Some(base) = study.case(&other.case) else {
            continue;
        };
        let _ = write!(
            md,
            "| {} | {} |",
            other.case.scheme.label(),
            other.case.mass.paper_label()
        );
        let mut largest: Option<(f64, Norm, usize)> = None;
        for &norm in &study.norms {
            let (Some(a), Some(b)) = (base.norm(norm), other.norm(norm)) else {
                let _ = write!(md, " — |");
                continue;
            };
            let rate = |r: &crate::harness::study::NormRates| {
                r.fit.map_or("—".to_string(), |f| format!("{:.3}", f.rate))
            };
            let _ = write!(md, " {} / {} |", rate(a), rate(b));
            for ((ea, eb), level) in a.errors.iter().zip(&b.errors).zip(&base.levels) {
                let change = (eb / ea - 1.0).abs();
                if change.is_finite() && largest.is_none_or(|(m, _, _)| change > m) {
                    largest = Some((change, norm, level.nx));
                }
            }
        }
        match largest {
            Some((change, norm, nx)) => {
                let _ = writeln!(md, " {:.1} % ({}, NX = {nx}) |", 100.0 * change, norm.key());
            }
            None => md.push_str(" — |\n"),
        }
    }
    md
}
