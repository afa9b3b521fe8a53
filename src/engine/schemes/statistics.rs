//! What a scheme's steps have cost so far and how well they kept the contact condition: one
//! value for every integrator ([`super::TimeIntegrator::statistics`]), read from the parts that
//! do the work (the step matrix's solver counts its solves, each contact step its
//! complementarity solves, their seconds and the largest violation).

use crate::engine::contact::{ContactStep, Truncation};
use crate::engine::linalg::SolveCounts;

/// The work and the contact accuracy of a run's steps so far.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepStatistics {
    /// How many steps needed a complementarity solve.
    pub contact_solves: usize,
    /// Wall-clock seconds spent in those solves.
    pub contact_seconds: f64,
    /// The largest complementarity violation of any step so far (on the constrained quantity
    /// of the scheme: `u^{n+1}`, or `(u^{n+1} + e u^{n−1})/(1 + e)` for Paoli–Schatzman; NaN
    /// where it is unknown, another code's run replayed).
    pub complementarity_violation: f64,
    /// The step matrix's solves so far and their CG iterations (none for a scheme without
    /// one, or that solves directly).
    pub step_solves: SolveCounts,
    /// The slab of the local contact operator ([`crate::engine::contact::local`]); `None` with
    /// the full operator or without contact.
    pub contact_truncation: Option<Truncation>,
}

impl StepStatistics {
    /// The statistics of a scheme whose step matrices' solvers counted `step_solves` and whose
    /// contact steps are `contacts` (the one that reports its slab first): their complementarity
    /// solves and seconds summed, the largest of their violations.
    pub fn of<'c>(
        step_solves: SolveCounts,
        contacts: impl IntoIterator<Item = &'c ContactStep>,
    ) -> Self {
        let mut statistics = Self {
            step_solves,
            ..Self::default()
        };
        for contact in contacts {
            statistics.contact_solves += contact.solves();
            statistics.contact_seconds += contact.seconds();
            statistics.complementarity_violation = statistics
                .complementarity_violation
                .max(contact.max_violation());
            statistics.contact_truncation = statistics
                .contact_truncation
                .or_else(|| contact.truncation());
        }
        statistics
    }

    /// These statistics after the contact work of `earlier` (a start step taken by another
    /// scheme): its complementarity solves and seconds added, its violation in the maximum.
    pub fn after_contact_of(self, earlier: &StepStatistics) -> Self {
        Self {
            contact_solves: earlier.contact_solves + self.contact_solves,
            contact_seconds: earlier.contact_seconds + self.contact_seconds,
            complementarity_violation: earlier
                .complementarity_violation
                .max(self.complementarity_violation),
            ..self
        }
    }
}
