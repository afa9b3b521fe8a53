//! The convergence figures (1D paper Figures 9–10, the note's Figures 3 and 8): error
//! against `Δx` per scheme and norm, one series per mass, with the fitted slopes drawn and,
//! against a fine-mesh reference, the reference's bias bound in their legends.

use crate::harness::problem::MassVariant;
use crate::harness::render::figures::{
    convergence_figure, ConvergenceFit, ConvergenceSeries, ErrorBand, Figure, FigureError,
};
use crate::harness::run::norms::Norm;
use crate::harness::study::sensitivity::{CaseSensitivity, Sensitivity};
use crate::harness::study::{CaseStudy, Study};

/// The legend of a mass variant's series or panel.
pub(super) fn panel_label(mass: MassVariant) -> String {
    format!("{} mass", mass.name())
}

/// One convergence figure per scheme and norm: the standard and the redistributed mass, with
/// the fitted slopes of the study.
///
/// A case that `sensitivity` classes as chaotic is drawn as its ensemble (its one unperturbed
/// run is just one sample of a distribution): the median error at each level, a band shaded
/// between the smallest and the largest, and the median of the members' rates with their
/// range. The other cases are drawn from the study as they are.
///
/// Errors: `Inconsistent` when `sensitivity` was run at other levels, ratio or horizon than
/// `study`, or lacks the errors of a norm of `study` for a chaotic case; the errors of
/// [`convergence_figure`].
pub fn convergence_figures(
    study: &Study,
    sensitivity: Option<&Sensitivity>,
) -> Result<Vec<Figure>, FigureError> {
    if let Some(s) = sensitivity {
        if s.config != study.config {
            return Err(FigureError::Inconsistent {
                what: format!(
                    "the sensitivity study ran with {:?}, the convergence study with {:?}",
                    s.config, study.config
                ),
            });
        }
    }
    convergence_figures_of(
        study,
        sensitivity,
        "convergence",
        "1D bar, ",
        &Against::Exact,
    )
}

/// What the errors of a study are measured against.
pub enum Against<'a> {
    /// The exact solution: titles say `‖u_h − u‖`, no bias.
    Exact,
    /// A fine-mesh reference, named in titles (`‖u_h − u_ref‖`, `u_ref` at `level` elements
    /// along the axis), with the bound on how far its bias moves a case's rate in a norm.
    Reference {
        /// Elements along the axis of the reference.
        level: usize,
        /// The rate-bias bound of a case in a norm (`None`: unbounded).
        bias: &'a dyn Fn(&CaseStudy, Norm) -> Option<f64>,
    },
}

/// [`convergence_figures`] without a sensitivity study, against `against`, with files named
/// `<prefix>-<scheme>-<norm>.svg` and titles starting with `title_prefix`.
pub fn convergence_figures_named(
    study: &Study,
    prefix: &str,
    title_prefix: &str,
    against: &Against<'_>,
) -> Result<Vec<Figure>, FigureError> {
    convergence_figures_of(study, None, prefix, title_prefix, against)
}

/// A norm's label with the reference named as one: `‖u_h − u_ref‖ …` for `‖u_h − u‖ …`.
pub(super) fn reference_label(norm: Norm) -> String {
    norm.label()
        .replace("− u‖", "− u_ref‖")
        .replace("− λ‖", "− λ_ref‖")
        .replace("− E‖", "− E_ref‖")
}

fn convergence_figures_of(
    study: &Study,
    sensitivity: Option<&Sensitivity>,
    prefix: &str,
    title_prefix: &str,
    against: &Against<'_>,
) -> Result<Vec<Figure>, FigureError> {
    let mut out = Vec::new();
    let mut schemes: Vec<_> = study.cases.iter().map(|c| c.case.scheme).collect();
    schemes.dedup();
    for scheme in schemes {
        for &norm in &study.norms {
            let mut series = Vec::new();
            let mut bias = Vec::new();
            for c in study.cases.iter().filter(|c| c.case.scheme == scheme) {
                let chaotic = sensitivity
                    .and_then(|s| s.case(&c.case.id()))
                    .filter(|e| e.chaotic);
                if let Some(s) = convergence_series(c, norm, chaotic, &panel_label(c.case.mass))? {
                    series.push(s);
                    if let Against::Reference { bias: b, .. } = against {
                        bias.push(b(c, norm));
                    }
                }
            }
            let (what, fit) = match against {
                Against::Exact => (norm.label().to_owned(), ConvergenceFit::Exact),
                Against::Reference { level, .. } => (
                    format!(
                        "{}, u_ref on {level} elements along the axis",
                        reference_label(norm)
                    ),
                    ConvergenceFit::Reference(bias),
                ),
            };
            out.push((
                format!("{prefix}-{}-{}.svg", scheme.name(), norm.key()),
                convergence_figure(
                    &format!("{title_prefix}{}, both masses: {what}", scheme.label()),
                    &series,
                    &fit,
                )?,
            ));
        }
    }
    Ok(out)
}

/// The series of `case`'s errors in `norm`, its legend starting with `label` (`None` when the
/// study did not compute it): from `chaotic`, the case's ensemble, when given (the median error
/// at each level, the min–max band and the members' rates); from the study's one run otherwise.
pub(super) fn convergence_series(
    case: &CaseStudy,
    norm: Norm,
    chaotic: Option<&CaseSensitivity>,
    label: &str,
) -> Result<Option<ConvergenceSeries>, FigureError> {
    let Some(rates) = case.norm(norm) else {
        return Ok(None);
    };
    let h: Vec<f64> = case.levels.iter().map(|l| l.h).collect();
    let Some(ensemble) = chaotic else {
        return Ok(Some(ConvergenceSeries {
            label: label.to_owned(),
            h,
            errors: rates.errors.clone(),
            fit: rates.fit,
            band: None,
        }));
    };
    let spreads = ensemble
        .errors
        .get(norm.key())
        .filter(|levels| levels.len() == h.len())
        .ok_or_else(|| FigureError::Inconsistent {
            what: format!(
                "the sensitivity study of {} has no errors in {} at the {} levels of the \
                 convergence study",
                ensemble.case,
                norm.key(),
                h.len()
            ),
        })?;
    Ok(Some(ConvergenceSeries {
        label: format!(
            "{label}: median of {} round-off runs (chaotic)",
            ensemble.members
        ),
        h,
        errors: spreads.iter().map(|s| s.median).collect(),
        fit: None,
        band: Some(ErrorBand {
            lower: spreads.iter().map(|s| s.min).collect(),
            upper: spreads.iter().map(|s| s.max).collect(),
            rate: ensemble.rates.get(norm.key()).copied(),
        }),
    }))
}
