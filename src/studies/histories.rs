//! The contact and energy histories behind the paper's Figures 7–8 and 11–22 (`make report`):
//! every scheme of the tables with both masses at [`HISTORY_LEVELS`] ([`HistoryJobs`]), one
//! file `data/histories/<scheme>.json` ([`SchemeHistories`]) per scheme, which `make figures`
//! reads.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::harness::files::artifacts::write_json_compact;
use crate::harness::problem::{MassVariant, Problem1d, Scheme};
use crate::harness::run::{run, BarRun, Observables, RunConfig};
use crate::harness::study::executor::JobList;
use crate::harness::study::{by_case, Case, CaseLevels, StudyConfig};
use crate::studies::benchmark::dirichlet;
use crate::studies::error::Error;

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
    pub runs: Vec<(MassVariant, usize, BarRun)>,
}

/// The runs behind the figures' histories as a job list ([`HistoryJobs::list`]): every scheme
/// of the tables with both masses at some levels, with the contact and energy histories, on the
/// Tables 1–2 benchmark.
pub struct HistoryJobs<'a> {
    problem: Problem1d,
    config: StudyConfig,
    schemes: Vec<Scheme>,
    cases: Vec<Case>,
    levels: &'a [usize],
}

impl<'a> HistoryJobs<'a> {
    /// The runs at `levels` of the benchmark under the repository root `root`.
    pub fn new(root: &Path, levels: &'a [usize]) -> Result<Self, Error> {
        let config = StudyConfig::paper_default();
        let schemes = Scheme::paper_schemes();
        Ok(Self {
            problem: dirichlet(root, config.horizon)?,
            config,
            cases: Case::matrix(&schemes, &MassVariant::PAPER),
            schemes: schemes.to_vec(),
            levels,
        })
    }

    /// The jobs: case `c` at level `l` is job `c · levels + l` ([`CaseLevels`]); a run that
    /// stops is an error.
    pub fn list(&self) -> impl JobList<Output = BarRun> + '_ {
        CaseLevels::new(self.cases.len(), self.levels, |c, l| {
            let config = RunConfig {
                nx: self.levels[l],
                ratio: self.config.ratio,
                scheme: self.cases[c].scheme,
                mass: self.cases[c].mass,
                observables: Observables {
                    contact_history: true,
                    energy_history: true,
                    ..Observables::default()
                },
                settings: self.config.settings,
            };
            run(&self.problem, &config, &mut [])?.completed()
        })
    }

    /// Every scheme's histories from the list's runs (`runs`, in its order).
    pub fn reduce(&self, runs: Vec<BarRun>) -> Vec<SchemeHistories> {
        let levels = self.levels;
        let mut per_case = self.cases.iter().zip(by_case(runs, levels.len()));
        self.schemes
            .iter()
            .map(|scheme| SchemeHistories {
                scheme: scheme.name(),
                label: scheme.label(),
                runs: per_case
                    .by_ref()
                    .take(MassVariant::PAPER.len())
                    .flat_map(|(case, runs)| {
                        levels.iter().zip(runs).map(|(&nx, r)| (case.mass, nx, r))
                    })
                    .collect(),
            })
            .collect()
    }
}

/// Writes each scheme's `histories` to `data/histories/<scheme>.json` under `out_dir` (the
/// figures' input).
pub fn write_histories(histories: &[SchemeHistories], out_dir: &Path) -> Result<(), Error> {
    for h in histories {
        write_json_compact(&out_dir.join(histories_file(&h.scheme)), h)?;
    }
    Ok(())
}
