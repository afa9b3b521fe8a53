//! The files of one run, what `signorini run --out DIR` writes: `run.json` (the whole result)
//! and the histories the scene asks for as CSV. A 1D run writes `contact.csv`,
//! `multiplier.csv`, `points.csv`, `field-t<T>.csv`, `strain-t<T>.csv` and `energy.csv`; a 2D/3D
//! box run `energy.csv` and `contact.csv` (its own columns), and its VTK files
//! (`crate::harness::run::elastic`, `crate::harness::run::paraview`). The gravity benchmark's
//! figure data (`crate::studies::gravity`) reuse the point and strain tables.

use crate::harness::files::artifacts::csv;
use crate::harness::run::elastic::BoxObservations;
use crate::harness::run::{BarObservations, FieldSnapshot, PointHistory};

/// The whole result of a run, as JSON ([`crate::harness::run::RunResult`]).
pub const RUN_JSON: &str = "run.json";

/// The digits after the point of every number in a run's CSV files (all of an `f64`).
pub const RUN_CSV_DIGITS: usize = 17;

/// The displacement at the observed points over time, computed and exact:
/// `time,u_h(x=X),u(x=X),…`.
pub fn points_csv(p: &PointHistory, digits: usize) -> String {
    let header: Vec<String> = std::iter::once("time".to_string())
        .chain(
            p.x.iter()
                .flat_map(|x| [format!("u_h(x={x})"), format!("u(x={x})")]),
        )
        .collect();
    let mut columns: Vec<&[f64]> = vec![&p.time];
    for (h, e) in p.displacement.iter().zip(&p.displacement_exact) {
        columns.push(h);
        columns.push(e);
    }
    csv(&header.join(","), &columns, digits)
}

/// The strain of a field snapshot along the bar, computed and exact:
/// `x_mid,strain,strain_exact`.
pub fn strain_csv(f: &FieldSnapshot, digits: usize) -> String {
    csv(
        "x_mid,strain,strain_exact",
        &[&f.x_mid, &f.strain, &f.strain_exact],
        digits,
    )
}

/// The name of the strain table of the snapshot requested at `requested_time`, after `prefix`
/// (`strain-t0.5.csv` for a run, `strain-<mass>-t0.5.csv` for the gravity benchmark).
pub fn strain_csv_name(prefix: &str, requested_time: f64) -> String {
    format!("{prefix}-t{requested_time}.csv")
}

/// The histories of a 1D run (what it observed) as (file name, CSV text).
pub fn history_csv(result: &BarObservations) -> Vec<(String, String)> {
    let digits = RUN_CSV_DIGITS;
    let mut files = Vec::new();
    if let Some(c) = &result.contact_history {
        files.push((
            "contact.csv".to_string(),
            csv(
                "time,displacement,displacement_exact",
                &[&c.time, &c.displacement, &c.displacement_exact],
                digits,
            ),
        ));
        files.push((
            "multiplier.csv".to_string(),
            csv(
                "time,multiplier,multiplier_exact",
                &[&c.multiplier_time, &c.multiplier, &c.multiplier_exact],
                digits,
            ),
        ));
    }
    if let Some(p) = &result.point_history {
        files.push(("points.csv".to_string(), points_csv(p, digits)));
    }
    for f in &result.fields {
        files.push((
            format!("field-t{}.csv", f.requested_time),
            csv(
                "x,displacement,displacement_exact",
                &[&f.x, &f.displacement, &f.displacement_exact],
                digits,
            ),
        ));
        files.push((
            strain_csv_name("strain", f.requested_time),
            strain_csv(f, digits),
        ));
    }
    if let Some(e) = &result.energy_history {
        files.push((
            "energy.csv".to_string(),
            csv(
                "time,energy,energy_exact",
                &[&e.time, &e.energy, &e.energy_exact],
                digits,
            ),
        ));
    }
    files
}

/// The histories of a 2D/3D box run (what it observed) as (file name, CSV text): `energy.csv` and `contact.csv`.
pub fn box_history_csv(result: &BoxObservations) -> Vec<(String, String)> {
    let digits = RUN_CSV_DIGITS;
    let (t, e): (Vec<f64>, Vec<f64>) = result.energy.iter().copied().unzip();
    let c = &result.contact;
    vec![
        (
            "energy.csv".to_string(),
            csv("time,energy", &[&t, &e], digits),
        ),
        (
            "contact.csv".to_string(),
            csv(
                "time,mean_gap,centre_gap,total_force,centre_multiplier",
                &[
                    &c.time,
                    &c.mean_gap,
                    &c.centre_gap,
                    &c.total_force,
                    &c.centre_multiplier,
                ],
                digits,
            ),
        ),
    ]
}
