//! The note's Figures 1–8 from a 2D/3D study's data (`elastic-<d>d.json` and
//! `data/elastic-<d>d-histories.json`), for each scheme: the contact face's centre node
//! (Figures 1, 6), the energy (2, 7), the convergence curves with fitted slopes (3, 8) and the
//! von Mises stress along the bar over time (4–5), standard mass left, redistributed right,
//! always with the fine-mesh reference where the figure has one.

use super::from_reports::{convergence_figures_named, Figure};
use super::heatmap::{space_time_map, SpaceTimePanel};
use super::{contact_node_figure, energy_figure, ContactPanel, EnergyPanel, FigureError};
use crate::elastic_study::{CaseHistories, ElasticHistories, ElasticStudy, ReferenceCurves};
use crate::fem::MassVariant;
use crate::run::{ContactHistory, EnergyHistory};
use crate::schemes::Scheme;

fn reference_contact(r: &ReferenceCurves) -> ContactHistory {
    ContactHistory {
        time: r.time.clone(),
        displacement: r.centre_displacement.clone(),
        multiplier_time: r.time.clone(),
        multiplier: r.centre_multiplier.clone(),
        ..ContactHistory::default()
    }
}

fn case_contact(c: &CaseHistories, gap: f64) -> ContactHistory {
    ContactHistory {
        time: c.contact.time.clone(),
        displacement: c.contact.centre_gap.iter().map(|g| g - gap).collect(),
        multiplier_time: c.contact.time.clone(),
        multiplier: c.contact.centre_multiplier.clone(),
        ..ContactHistory::default()
    }
}

fn energy_of(time: Vec<f64>, energy: Vec<f64>) -> EnergyHistory {
    EnergyHistory {
        time,
        energy,
        energy_exact: Vec::new(),
    }
}

/// Every figure of one study.
pub fn elastic_figures(
    study: &ElasticStudy,
    histories: &ElasticHistories,
) -> Result<Vec<Figure>, FigureError> {
    let gap = histories.obstacle_gap.unwrap_or(0.0);
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
        let contact: Vec<ContactPanel> = mine
            .iter()
            .map(|(mass, h)| ContactPanel {
                label: format!("{} mass", mass.name()),
                runs: vec![
                    (reference_label.clone(), reference_contact(reference)),
                    (level(h), case_contact(h, gap)),
                ],
            })
            .collect();
        let title = |what: &str| format!("{}D bar, {}: {what}", study.dimension, scheme.label());
        out.push((
            format!("{prefix}-contact-{}.svg", scheme.name()),
            contact_node_figure(&title("centre contact node"), &contact)?,
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
    out.extend(convergence_figures_named(
        &study.study,
        &format!("{prefix}-convergence"),
        &format!("{}D bar, ", study.dimension),
    )?);
    Ok(out)
}
