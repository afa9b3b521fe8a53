//! A bar's run: the observers of [`super::exact`] against the exact solution, the ones
//! `config.observables` asks for, around the one time loop.

use std::collections::BTreeMap;
use std::time::Instant;

use crate::engine::error::ParameterError;
use crate::engine::problem::Problem1d;
use crate::harness::files::error::Error;
use crate::harness::run::exact::{
    ContactRecorder, EnergyRecorder, ErrorObservers, FieldRecorder, PointRecorder,
};
use crate::harness::run::norms::Norm;
use crate::harness::run::{drive_with, BarObservations, Observer, RunConfig, RunResult};

/// Runs one configuration of a bar to its horizon with the observers `config.observables`
/// asks for, followed by the caller's `extra`.
pub(super) fn run_bar(
    problem: &Problem1d,
    config: &RunConfig,
    extra: &mut [&mut dyn Observer],
) -> Result<RunResult<BarObservations>, Error> {
    let clock = Instant::now();
    let observables = &config.observables;
    if problem.obstacle_gap.is_none() && observables.norms.contains(&Norm::MultiplierL2) {
        return Err(ParameterError::new(
            "norm",
            Norm::MultiplierL2,
            "a norm the problem defines (lambda_L2 needs an obstacle)",
        )
        .into());
    }
    let discretisation = problem.discretise(config.nx, config.mass, &config.settings)?;
    let bar = &discretisation.mesh;
    let model = &discretisation.model;
    let exact = problem.exact.as_ref();
    let mut errors =
        ErrorObservers::new(bar, exact, &observables.norms, observables.contact_history);
    let mut contact = observables
        .contact_history
        .then(|| ContactRecorder::new(bar, exact));
    let mut energy_history = observables
        .energy_history
        .then(|| EnergyRecorder::new(exact));
    let mut points = (!observables.points.is_empty())
        .then(|| PointRecorder::new(bar, exact, &observables.points));
    let mut fields = FieldRecorder::new(bar, exact, &observables.fields_at);
    let mut own: Vec<&mut dyn Observer> = vec![&mut fields];
    own.extend(points.as_mut().map(|o| o as &mut dyn Observer));
    own.extend(errors.observers());
    own.extend(contact.as_mut().map(|o| o as &mut dyn Observer));
    own.extend(energy_history.as_mut().map(|o| o as &mut dyn Observer));
    let stepped = drive_with(
        &discretisation,
        problem.horizon,
        (config, None),
        own,
        extra,
        clock,
    )?;
    let completed = stepped.status.is_completed();
    let balance = stepped
        .max_balance_residual
        .filter(|_| observables.energy_balance && completed);
    let observed = BarObservations {
        nx: config.nx,
        h: bar.h(),
        dof_steps: stepped.steps * model.n_dofs(),
        errors: if completed {
            errors.norms(&observables.norms)
        } else {
            BTreeMap::new()
        },
        space_norm_evaluations: errors.displacement.as_ref().map_or(0, |d| d.evaluations()),
        multiplier_variation: errors
            .multiplier
            .as_ref()
            .and_then(|m| m.variation())
            .filter(|_| completed),
        contact_history: contact.map(|c| c.history),
        energy_history: energy_history.map(|e| e.history),
        point_history: points.map(|p| p.history),
        fields: fields.snapshots,
    };
    Ok(RunResult::of(
        &stepped,
        model.n_dofs(),
        problem.contact.name(),
        balance,
        observed,
    ))
}
