//! The contact and energy histories behind the paper's Figures 7–8 and 11–22 (`make report`):
//! every scheme of the tables with both masses at [`HISTORY_LEVELS`], one file
//! `data/histories/<scheme>.json` ([`SchemeHistories`]) per scheme, which `make figures` reads.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::harness::files::artifacts::write_json_compact;
use crate::harness::files::error::Error;
use crate::harness::problem::{MassVariant, Scheme};
use crate::harness::run::{run, Observables, RunConfig, RunResult};
use crate::harness::study::executor::run_local;
use crate::harness::study::{by_case, Case, CaseLevels, StudyConfig};
use crate::studies::benchmark::dirichlet;

/// The levels whose contact and energy histories `make report` keeps for the figures.
pub const HISTORY_LEVELS: [usize; 3] = [10, 20, 40];

/// The directory of the history files, under a reports directory.
pub const HISTORIES_DIR: &str = "data/histories";

/// The history file of the scheme named `scheme`, under a reports directory.
pub fn histories_file(scheme: &str) -> String {
    format!("{HISTORIES_DIR}/{scheme}.json")
}

/// The runs of one scheme with both masses at a few levels (what `contact-` and `energy-`
/// figures draw).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SchemeHistories {
    /// Preset name of the scheme.
    pub scheme: String,
    /// The paper's label.
    pub label: String,
    /// `(mass, NX, run)` with contact and energy histories.
    pub runs: Vec<(MassVariant, usize, RunResult)>,
}

/// For every scheme of the tables, runs both masses at `levels` with the contact and energy
/// histories and writes them to `data/histories/<scheme>.json` (the figures' input).
pub fn write_histories(root: &Path, out_dir: &Path, levels: &[usize]) -> Result<(), Error> {
    let config = StudyConfig::paper_default();
    let problem = dirichlet(root, config.horizon)?;
    let schemes = Scheme::paper_schemes();
    let cases = Case::matrix(&schemes, &MassVariant::PAPER);
    let runs = run_local(&CaseLevels::new(cases.len(), levels, |c, l| {
        let config = RunConfig {
            nx: levels[l],
            ratio: config.ratio,
            scheme: cases[c].scheme,
            mass: cases[c].mass,
            observables: Observables {
                contact_history: true,
                energy_history: true,
                ..Observables::default()
            },
            settings: config.settings,
        };
        run(&problem, &config)?.completed()
    }))?;
    let mut per_case = cases.iter().zip(by_case(runs, levels.len()));
    let histories = schemes.iter().map(|scheme| SchemeHistories {
        scheme: scheme.name(),
        label: scheme.label(),
        runs: per_case
            .by_ref()
            .take(MassVariant::PAPER.len())
            .flat_map(|(case, runs)| levels.iter().zip(runs).map(|(&nx, r)| (case.mass, nx, r)))
            .collect(),
    });
    for h in histories {
        write_json_compact(&out_dir.join(histories_file(&h.scheme)), &h)?;
    }
    Ok(())
}
