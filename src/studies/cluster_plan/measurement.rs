//! What a computed reference cost on this machine (`signorini reference --measure FILE`): the
//! figures the cluster plan's cost model is fitted to ([`super::fit`]).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::harness::files::artifacts::write_atomic;
use crate::harness::files::error as files;
use crate::harness::files::input::{self, Limit};
use crate::harness::reference::fine_mesh::fine_run::FineReference;
use crate::harness::run::distributed::{Ranks, Traffic};
use crate::harness::study::budget::peak_resident_bytes;
use crate::studies::error::Error;

/// The `format` of a measurement file.
pub const MEASUREMENT_FORMAT: &str = "signorini-reference-measurement/2";

/// What a rank sent and summed over the fine run (a distributed run's rank 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct MeasuredTraffic {
    /// Point-to-point messages sent.
    pub messages: u64,
    /// Their bytes.
    pub bytes_sent: u64,
    /// Bytes received point to point.
    pub bytes_received: u64,
    /// Collective sums taken part in.
    pub sums: u64,
}

/// One computed reference, measured: the fields of `--measure`'s JSON file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measurement {
    /// [`MEASUREMENT_FORMAT`].
    pub format: String,
    /// The scene's name.
    pub scene: String,
    /// Elements along the axis.
    pub level: usize,
    /// Unknowns.
    pub dofs: usize,
    /// Time steps.
    pub steps: usize,
    /// Processes the run was shared by (1: one process).
    pub ranks: usize,
    /// Threads of each process's pool (`RAYON_NUM_THREADS`).
    pub threads: usize,
    /// Processes the check run was shared by: `ranks` when it ran distributed beside the
    /// reference, 1 when it ran in one process beside rank 0.
    pub check_ranks: usize,
    /// The check run's unknowns.
    pub check_dofs: usize,
    /// Set-up seconds (rank 0's).
    pub setup_seconds: f64,
    /// Seconds of the steps, contact solves included (rank 0's).
    pub step_seconds: f64,
    /// Seconds of the contact solves, of `step_seconds` (rank 0's).
    pub contact_seconds: f64,
    /// `L`, the layers of the local contact operator's slab around `Γ_Sig` (rank 0 holds
    /// them and the next); `None` without one.
    pub contact_layers: Option<usize>,
    /// Seconds of the observers (projections, check, histories; rank 0's).
    pub observe_seconds: f64,
    /// Step systems solved.
    pub solves: usize,
    /// CG iterations over all of them.
    pub iterations: usize,
    /// Each rank's peak resident bytes, in rank order (0 where it could not be read).
    pub peak_bytes: Vec<u64>,
    /// Rank 0's traffic; `None` for one process.
    pub traffic: Option<MeasuredTraffic>,
}

impl Measurement {
    /// The measurement of `reference` (computed now) of scene `scene`, with every rank's peak
    /// memory gathered (every rank calls it together; rank 0's is the measurement, the others
    /// get `None`). `None` on rank 0 too when the reference was read from a cache.
    pub fn gather(
        scene: &str,
        reference: Option<&FineReference>,
        ranks: Option<&dyn Ranks>,
    ) -> Option<Self> {
        let own_peak = peak_resident_bytes().unwrap_or(0);
        let peak_bytes = match ranks {
            Some(r) => {
                let mut peaks = vec![0.0; r.size()];
                r.gather_all(own_peak as f64, &mut peaks);
                peaks.iter().map(|&p| p as u64).collect()
            }
            None => vec![own_peak],
        };
        let reference = reference?;
        let cost = reference.cost?;
        let h = &reference.histories;
        let traffic = ranks.and_then(|r| r.traffic()).map(
            |Traffic {
                 messages,
                 bytes_sent,
                 bytes_received,
                 sums,
             }| MeasuredTraffic {
                messages,
                bytes_sent,
                bytes_received,
                sums,
            },
        );
        Some(Self {
            format: MEASUREMENT_FORMAT.to_string(),
            scene: scene.to_string(),
            level: h.key.n_axis,
            dofs: h.dofs,
            steps: h.steps,
            ranks: ranks.map_or(1, |r| r.size()),
            threads: rayon::current_num_threads(),
            check_ranks: cost.check_ranks,
            check_dofs: h.check.dofs,
            setup_seconds: cost.timings.setup,
            step_seconds: cost.timings.stepping + cost.timings.contact,
            contact_seconds: cost.timings.contact,
            contact_layers: cost.contact_layers,
            observe_seconds: cost.timings.observe,
            solves: cost.solves,
            iterations: cost.iterations,
            peak_bytes,
            traffic,
        })
    }

    /// Rank 0's seconds per step, its observers included.
    pub fn seconds_per_step(&self) -> f64 {
        (self.step_seconds + self.observe_seconds) / self.steps.max(1) as f64
    }

    /// CG iterations per step.
    pub fn iterations_per_step(&self) -> f64 {
        self.iterations as f64 / self.steps.max(1) as f64
    }

    /// Writes it to `path` (whole or not at all).
    pub fn write(&self, path: &Path) -> Result<(), Error> {
        let json = serde_json::to_string_pretty(self).expect("a measurement serialises");
        Ok(write_atomic(path, json.as_bytes())?)
    }

    /// Reads a measurement file, refusing another format.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let measured: Self = input::read_json(path, MEASUREMENT_FILE)?;
        if measured.format != MEASUREMENT_FORMAT {
            return Err(crate::harness::files::error::ParameterError::new(
                "format",
                measured.format,
                MEASUREMENT_FORMAT,
            )
            .into());
        }
        measured.check(path)?;
        Ok(measured)
    }

    /// Refuses a measurement whose numbers cannot be one run's, naming the field: a count
    /// below 1 (level, unknowns, steps, ranks, threads, the check's), seconds that are negative
    /// or not finite, contact seconds beyond the steps' (they are part of them), or a peak
    /// memory list whose length is not the ranks'.
    fn check(&self, path: &Path) -> Result<(), Error> {
        let out_of_range = |field: &str, value: f64, allowed: &'static str| -> Error {
            files::Error::OutOfRange {
                path: path.to_path_buf(),
                field: field.to_string(),
                value,
                allowed,
            }
            .into()
        };
        for (field, count) in [
            ("level", self.level),
            ("dofs", self.dofs),
            ("steps", self.steps),
            ("ranks", self.ranks),
            ("threads", self.threads),
            ("check_ranks", self.check_ranks),
            ("check_dofs", self.check_dofs),
        ] {
            if count == 0 {
                return Err(out_of_range(field, 0.0, "at least 1"));
            }
        }
        for (field, seconds) in [
            ("setup_seconds", self.setup_seconds),
            ("step_seconds", self.step_seconds),
            ("contact_seconds", self.contact_seconds),
            ("observe_seconds", self.observe_seconds),
        ] {
            if !(seconds.is_finite() && seconds >= 0.0) {
                return Err(out_of_range(
                    field,
                    seconds,
                    "a finite number of seconds, at least 0",
                ));
            }
        }
        if self.contact_seconds > self.step_seconds {
            return Err(out_of_range(
                "contact_seconds",
                self.contact_seconds,
                "at most step_seconds (the contact solves are part of the steps)",
            ));
        }
        if self.peak_bytes.len() != self.ranks {
            return Err(out_of_range(
                "peak_bytes",
                self.peak_bytes.len() as f64,
                "one peak per rank (as many entries as ranks)",
            ));
        }
        Ok(())
    }
}

/// The size a measurement file may have.
const MEASUREMENT_FILE: Limit = Limit {
    what: "reference measurement",
    max_bytes: 1024 * 1024,
};
