//! The exact solution as a study's reference: a bar's run measured while it steps by the run's
//! own error observers against the closed-form solution its problem declares (the 1D paper's
//! Appendix), in the norms the study asks for.

use std::collections::BTreeSet;

use crate::harness::files::error as files;
use crate::harness::problem::Settings;
use crate::harness::run::norms::Norm;
use crate::harness::run::{run, Observables, Problem1d, RunConfig};
use crate::harness::study::error::Error;
use crate::harness::study::executor::run_local;
use crate::harness::study::{
    Case, LevelMeasure, LevelOutcome, Measured, Study, StudyConfig, StudyJobs,
};

/// A bar's runs against its exact solution: the run's own error observers measure the
/// requested norms while it steps.
pub struct ExactSolution<'a> {
    problem: &'a Problem1d,
    ratio: f64,
    settings: Settings,
    observables: Observables,
}

impl<'a> ExactSolution<'a> {
    /// The study of `cases` of the bar `problem` at the levels of `config` against its exact
    /// solution, evaluating `norms`; its configuration checked.
    pub fn jobs(
        problem: &'a Problem1d,
        cases: &'a [Case],
        norms: &BTreeSet<Norm>,
        config: &'a StudyConfig,
    ) -> Result<StudyJobs<'a, Self>, Error> {
        config.validate()?;
        let measure = ExactSolution {
            problem,
            ratio: config.ratio,
            settings: config.settings,
            observables: Observables {
                norms: norms.clone(),
                ..Observables::default()
            },
        };
        Ok(StudyJobs::measured_by(measure, cases, norms, config))
    }
}

impl LevelMeasure for ExactSolution<'_> {
    type Kept = ();

    fn measure(&self, case: Case, level: usize) -> Result<Measured<()>, files::Error> {
        let config = RunConfig {
            nx: level,
            ratio: self.ratio,
            scheme: case.scheme,
            mass: case.mass,
            observables: self.observables.clone(),
            settings: self.settings,
        };
        let outcome = LevelOutcome::of_bar_run(run(self.problem, &config, &mut [])?);
        Ok(Measured { outcome, kept: () })
    }
}

/// Runs every case of a bar at every level (in parallel over case × level, largest levels
/// first) and fits the rates of every norm in `norms`. Only those norms are evaluated.
pub fn run_study(
    problem: &Problem1d,
    cases: &[Case],
    norms: &BTreeSet<Norm>,
    config: &StudyConfig,
) -> Result<Study, Error> {
    let jobs = ExactSolution::jobs(problem, cases, norms, config)?;
    let ran = run_local(&jobs.list())?;
    Ok(jobs.reduce(ran, cases))
}
