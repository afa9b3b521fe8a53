//! The note's Figures 1–8 from a 2D/3D study's data (`elastic-<d>d.json` and
//! `data/elastic-<d>d-histories.json`), for each scheme: the contact face's centre node
//! (Figures 1, 6), the energy (2, 7), the von Mises stress along the bar over time (4–5), from
//! both; the convergence curves with fitted slopes and the reference's bias bounds (3, 8), from
//! the study alone. Standard mass left, redistributed right, always with the fine-mesh
//! reference where the figure has one.

use super::convergence::{convergence_figures_named, Against};
use crate::harness::problem::{MassVariant, Scheme};
use crate::harness::reference::fine_mesh::{CaseHistories, ElasticHistories, ReferenceCurves};
use crate::harness::render::figures::heatmap::{space_time_map, SpaceTimePanel};
use crate::harness::render::figures::{
    contact_node_figure, energy_figure, ContactAxes, ContactPanel, EnergyPanel, Figure, FigureError,
};
use crate::harness::run::{ContactHistory, EnergyHistory};
use crate::studies::elastic_study::ElasticStudy;

/// "No exact value" at each of `n` samples: the figures skip non-finite points, so the exact
/// curve of a box (which has none) is simply not drawn.
fn no_exact(n: usize) -> Vec<f64> {
    vec![f64::NAN; n]
}

/// The history of the centre contact node, its multiplier divided by the node's share of the
/// contact face `h^{d−1}` (a pressure, comparable across meshes: the nodal force itself scales
/// with the element, the "different scaling" the note mentions under its Figure 1).
fn contact_history(
    time: &[f64],
    displacement: Vec<f64>,
    multiplier: &[f64],
    share: f64,
) -> ContactHistory {
    ContactHistory {
        time: time.to_vec(),
        displacement,
        displacement_exact: no_exact(time.len()),
        multiplier_time: time.to_vec(),
        multiplier: multiplier.iter().map(|l| l / share).collect(),
        multiplier_exact: no_exact(time.len()),
    }
}

fn reference_contact(r: &ReferenceCurves, d: usize) -> ContactHistory {
    let share = r.element_size.powi(d as i32 - 1);
    contact_history(
        &r.time,
        r.centre_displacement.clone(),
        &r.centre_multiplier,
        share,
    )
}

fn case_contact(c: &CaseHistories, gap: f64, d: usize) -> ContactHistory {
    let displacement = c.contact.centre_gap.iter().map(|g| g - gap).collect();
    let share = c.element_size.powi(d as i32 - 1);
    contact_history(
        &c.contact.time,
        displacement,
        &c.contact.centre_multiplier,
        share,
    )
}

fn energy_of(time: Vec<f64>, energy: Vec<f64>) -> EnergyHistory {
    EnergyHistory {
        energy_exact: no_exact(time.len()),
        time,
        energy,
    }
}

/// The convergence figures of one study (`elastic-<d>d-convergence-<scheme>-<norm>.svg`),
/// against its fine-mesh reference, with each case's rate-bias bound.
pub fn elastic_convergence_figures(study: &ElasticStudy) -> Result<Vec<Figure>, FigureError> {
    let bias = |c: &crate::harness::study::CaseStudy, n| study.reference.case_bias(c, n);
    convergence_figures_named(
        &study.study,
        &format!("elastic-{}d-convergence", study.dimension),
        &format!("{}D bar, ", study.dimension),
        &Against::Reference {
            level: study.config.reference_level,
            bias: &bias,
        },
    )
}

/// The figures of one study drawn from its histories: contact node, energy and von Mises
/// stress per scheme.
pub fn elastic_figures(
    study: &ElasticStudy,
    histories: &ElasticHistories,
) -> Result<Vec<Figure>, FigureError> {
    let gap = histories.obstacle_gap.unwrap_or(0.0);
    let d = study.dimension;
    let prefix = format!("elastic-{}d", study.dimension);
    let reference = &histories.reference;
    let reference_label = format!("reference, {} elements along the axis", reference.level);
    let mut schemes: Vec<Scheme> = study.study.cases.iter().map(|c| c.case.scheme).collect();
    schemes.dedup();
    let mut out = Vec::new();
    for scheme in schemes {
        let mine: Vec<(MassVariant, &CaseHistories)> = study
            .study
            .cases
            .iter()
            .filter(|c| c.case.scheme == scheme)
            .filter_map(|c| {
                let id = c.case.id();
                Some((c.case.mass, histories.cases.iter().find(|h| h.case == id)?))
            })
            .collect();
        if mine.is_empty() {
            continue;
        }
        let level = |h: &CaseHistories| format!("{} elements along the axis", h.level);
        let mut levels: Vec<usize> = mine.iter().map(|(_, h)| h.level).collect();
        levels.dedup();
        let levels: Vec<String> = levels.iter().map(|l| l.to_string()).collect();
        let masses = match mine.as_slice() {
            [(one, _)] => format!("{} mass", one.name()),
            _ => "standard (left) and redistributed (right) mass".to_owned(),
        };
        let contact: Vec<ContactPanel> = mine
            .iter()
            .map(|(mass, h)| ContactPanel {
                label: format!("{} mass", mass.name()),
                runs: vec![
                    (reference_label.clone(), reference_contact(reference, d)),
                    (level(h), case_contact(h, gap, d)),
                ],
            })
            .collect();
        let title = |what: &str| {
            format!(
                "{}D bar, {}, {} elements (reference {}), {masses}: {what}",
                study.dimension,
                scheme.label(),
                levels.join(", "),
                reference.level
            )
        };
        out.push((
            format!("{prefix}-contact-{}.svg", scheme.name()),
            contact_node_figure(
                &title("centre contact node"),
                ContactAxes {
                    displacement: "u_n(centre, t)",
                    multiplier: if d == 2 {
                        "λ/h (pressure)"
                    } else {
                        "λ/h² (pressure)"
                    },
                },
                &contact,
            )?,
        ));
        let energy: Vec<EnergyPanel> = mine
            .iter()
            .map(|(mass, h)| EnergyPanel {
                label: format!("{} mass", mass.name()),
                runs: vec![
                    (
                        reference_label.clone(),
                        energy_of(reference.time.clone(), reference.energy.clone()),
                    ),
                    (
                        level(h),
                        energy_of(
                            h.energy.iter().map(|e| e.0).collect(),
                            h.energy.iter().map(|e| e.1).collect(),
                        ),
                    ),
                ],
            })
            .collect();
        out.push((
            format!("{prefix}-energy-{}.svg", scheme.name()),
            energy_figure(&title("energy"), &energy)?,
        ));
        let stress: Vec<SpaceTimePanel> = mine
            .iter()
            .map(|(mass, h)| SpaceTimePanel {
                label: format!("{} mass", mass.name()),
                time: h.stress.time.clone(),
                position: h.stress.position.clone(),
                values: h.stress.von_mises.clone(),
            })
            .collect();
        out.push((
            format!("{prefix}-von-mises-{}.svg", scheme.name()),
            space_time_map(&title("von Mises stress along the axis"), &stress)?,
        ));
    }
    Ok(out)
}
