//! Another code's run in memory ([`ExternalRun`]), as the JSON and CSV readers hand it over,
//! the limits a file must respect, and the checks of its content against the scene it claims
//! to solve ([`ExternalRun::check_against`]): the scene's name, a uniform P1 mesh of the
//! scene's bar, sample times from 0 to the horizon, a clamped end at rest, and what the
//! format's version allows ([`Version`]).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::error::ExternalError;
use crate::engine::fem::{EndCondition, MassVariant};
use crate::engine::problem::Problem1d;
use crate::engine::schemes::Scheme;
use crate::harness::files::input::Limit;

/// The format's first version, the first thing a file states (`format`).
pub const FORMAT: &str = "signorini-external/1";

/// The format's second version: the box form's, and the bar's with null values and declared
/// quantities ([`Version::Two`]).
pub const FORMAT_2: &str = "signorini-external/2";

/// What a code reports as its energy, when it does: the definitions a file may declare.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum EnergyDefinition {
    /// `½ VⁿᵀM Vⁿ + ½ UⁿᵀS Uⁿ` at the sample's time.
    TotalAtSample,
    /// A staggered energy `E^{n−½}` between the sample and the one before (Newmark's,
    /// Paoli–Schatzman's).
    Staggered,
    /// The total at the sample plus a contact term (penalty or Nitsche).
    TotalWithContactTerm,
}

impl EnergyDefinition {
    /// The names a file may give, for messages.
    pub const NAMES: &'static str = "total-at-sample, staggered, total-with-contact-term";

    /// The name a file gives it.
    pub fn name(self) -> &'static str {
        match self {
            EnergyDefinition::TotalAtSample => "total-at-sample",
            EnergyDefinition::Staggered => "staggered",
            EnergyDefinition::TotalWithContactTerm => "total-with-contact-term",
        }
    }
}

/// The versions of the format a bar's run file may state (`format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Version {
    /// [`FORMAT`]: every sample carries the same fields, every value a number; the energy
    /// norms measure the file's `energy`.
    One,
    /// [`FORMAT_2`], the version the box form has too: `lambda`, `displacement` and
    /// `velocity` may be null (not computed) at any sample; the energy norms measure the energy
    /// the harness computes from the fields with the declared `mass`, and a reported `energy`
    /// needs its `energy_definition` and is shown beside them.
    Two,
}

impl Version {
    /// The version the text `format` of the file `path` states.
    pub fn parse(path: &Path, format: &str) -> Result<Self, ExternalError> {
        match format {
            FORMAT => Ok(Version::One),
            FORMAT_2 => Ok(Version::Two),
            other => Err(ExternalError::invalid(
                path,
                "format",
                None,
                format!("{other:?}"),
                format!("{FORMAT:?} or {FORMAT_2:?}"),
            )),
        }
    }
}

/// The mass matrix `text` names (`mass`, version 2), refused naming the allowed names.
pub fn parse_mass(path: &Path, text: &str) -> Result<MassVariant, ExternalError> {
    text.parse::<MassVariant>()
        .map_err(|e| ExternalError::invalid(path, "mass", None, format!("{text:?}"), e.allowed))
}

/// The scheme `text` names (`scheme`, version 2: a preset or a parametrised form of
/// `signorini list`), refused naming the allowed forms.
pub fn parse_scheme(path: &Path, text: &str) -> Result<Scheme, ExternalError> {
    text.parse::<Scheme>().map_err(|e| {
        ExternalError::invalid(path, "scheme", None, format!("{text:?}"), e.to_string())
    })
}

/// The energy definition `text` names (`energy_definition`, version 2), refused naming the
/// allowed names.
pub fn parse_energy_definition(path: &Path, text: &str) -> Result<EnergyDefinition, ExternalError> {
    use serde::de::value::{Error, StrDeserializer};
    EnergyDefinition::deserialize(StrDeserializer::<Error>::new(text)).map_err(|_| {
        ExternalError::invalid(
            path,
            "energy_definition",
            None,
            format!("{text:?}"),
            format!("one of: {}", EnergyDefinition::NAMES),
        )
    })
}

/// The largest run file read, in bytes (256 MiB): a larger one is refused before it is read.
pub const MAX_FILE_BYTES: u64 = 256 * 1024 * 1024;

/// The most numbers one file may hold (2²⁴, 128 MiB as `f64`): mesh nodes plus samples × values
/// per sample. Reading a file takes at most three times that (the arrays grow by doubling).
pub const MAX_VALUES: usize = 1 << 24;

/// A run file, as [`crate::harness::files::input`] reads it.
pub const RUN_FILE: Limit = Limit {
    what: "run file",
    max_bytes: MAX_FILE_BYTES,
};

/// How far a node may be from `i L/NX`, relative to `L/NX` (uniformity and span of the mesh).
pub const MESH_TOLERANCE: f64 = 1e-9;

/// How far the last sample time may be from the horizon `T`, relative to `T`; a time above `T`
/// within it is read as `T`.
pub const HORIZON_TOLERANCE: f64 = 1e-9;

/// How far a clamped end's displacement or velocity may be from 0 (absolute).
pub const CLAMPED_TOLERANCE: f64 = 1e-12;

/// How far `contact_displacement` may be from the field's value at `x = 0`: relative to
/// `max(1, |u_0|)`.
pub const CONTACT_TOLERANCE: f64 = 1e-9;

/// The code that made a run.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Code {
    /// Its name.
    pub name: String,
    /// Its version.
    pub version: String,
}

/// How a sample index reads in messages: `samples[k]` in JSON, the line in CSV.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleOrigin {
    /// `samples[k]` of a JSON file.
    Json,
    /// A CSV file whose sample 0 is on this 1-based line.
    Csv {
        /// The line of sample 0.
        first_line: usize,
    },
}

impl SampleOrigin {
    /// Where sample `k` is in the file.
    pub fn at(self, k: usize) -> String {
        match self {
            SampleOrigin::Json => format!("samples[{k}]"),
            SampleOrigin::Csv { first_line } => format!("line {}", first_line + k),
        }
    }
}

/// A nodal field (`displacement`, `velocity`) at the samples that have it: their rows one
/// after another, and per sample where its row starts. A version 1 file has a row at every
/// sample; a version 2 file may leave any sample without one.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SampledField {
    values: Vec<f64>,
    /// Per sample, where its row starts in `values`; `None` for a sample without the field.
    rows: Vec<Option<usize>>,
}

impl SampledField {
    /// Starts sample `k`'s row (the samples before it that have none lack the field) and
    /// returns the values to append it to.
    pub fn begin_row(&mut self, k: usize) -> &mut Vec<f64> {
        self.rows.resize(k, None);
        self.rows.push(Some(self.values.len()));
        &mut self.values
    }

    /// Ends the field at `samples` samples: those after the last row lack it.
    pub fn finish(&mut self, samples: usize) {
        self.rows.resize(samples, None);
    }

    /// The nodal values of sample `k` (`nodes` per row), if it has the field.
    pub fn at(&self, k: usize, nodes: usize) -> Option<&[f64]> {
        self.rows[k].map(|start| &self.values[start..start + nodes])
    }

    /// The number of samples that have the field.
    pub fn sampled(&self) -> usize {
        self.rows.iter().flatten().count()
    }

    /// Whether every sample has the field.
    pub fn is_complete(&self) -> bool {
        self.rows.iter().all(Option::is_some)
    }
}

/// One run of another code, as read: every value finite, every per-sample series as long as
/// `time`, every field row as long as `nodes` (the readers check this). The rest is checked
/// against the scene by [`ExternalRun::check_against`].
#[derive(Debug, Clone, PartialEq)]
pub struct ExternalRun {
    /// The file it was read from.
    pub path: PathBuf,
    /// How sample indices read in messages.
    pub origin: SampleOrigin,
    /// The format's version the file states.
    pub version: Version,
    /// The scene's name (`bar1d-dirichlet`).
    pub scene: String,
    /// The code and its version.
    pub code: Code,
    /// The configuration: files with one label form one refinement series.
    pub label: String,
    /// The scheme the code ran (version 2), shown with the series and in the league table.
    pub scheme: Option<Scheme>,
    /// The mass matrix the code integrated (version 2): the energy is computed with it.
    pub mass: Option<MassVariant>,
    /// How the code enforces contact, in its words (version 2; shown, not interpreted).
    pub contact: Option<String>,
    /// What the reported `energy` is (version 2).
    pub energy_definition: Option<EnergyDefinition>,
    /// The mesh nodes `x_0 < … < x_NX`.
    pub nodes: Vec<f64>,
    /// The sample times `t_0 = 0 < … < t_N = T`.
    pub time: Vec<f64>,
    /// `u_h(x_i, t_n)` at the samples that have it.
    pub displacement: Option<SampledField>,
    /// `∂t u_h(x_i, t_n)`, like `displacement`.
    pub velocity: Option<SampledField>,
    /// The contact multiplier (stress) at `x = 0`, one per sample; `None` where the code did
    /// not compute it (version 2).
    pub lambda: Option<Vec<Option<f64>>>,
    /// The time each `lambda` approximates (default: the sample's).
    pub lambda_time: Option<Vec<f64>>,
    /// `u_h(0, t_n)`, one per sample.
    pub contact_displacement: Option<Vec<f64>>,
    /// The discrete energy the code reports, one per sample.
    pub energy: Option<Vec<f64>>,
    /// The time each `energy` approximates (default: the sample's).
    pub energy_time: Option<Vec<f64>>,
}

impl ExternalRun {
    /// `NX`, the number of elements.
    pub fn nx(&self) -> usize {
        self.nodes.len().saturating_sub(1)
    }

    /// The number of samples `N + 1`.
    pub fn samples(&self) -> usize {
        self.time.len()
    }

    /// The nodal values of `field` (`displacement`, `velocity`) at sample `k`, if it has them.
    pub fn row<'f>(&self, field: &'f Option<SampledField>, k: usize) -> Option<&'f [f64]> {
        field.as_ref()?.at(k, self.nodes.len())
    }

    /// The contact node's displacement at sample `k`: the file's `contact_displacement`, else
    /// the field's value at `x = 0`; `None` when the file has neither at that sample.
    pub fn contact_displacement_at(&self, k: usize) -> Option<f64> {
        match &self.contact_displacement {
            Some(c) => Some(c[k]),
            None => self.row(&self.displacement, k).map(|u| u[0]),
        }
    }

    /// The multiplier at sample `k`, if the file has it there.
    pub fn lambda_at(&self, k: usize) -> Option<f64> {
        self.lambda.as_ref().and_then(|l| l[k])
    }

    fn invalid(
        &self,
        field: impl Into<String>,
        at: Option<String>,
        value: impl std::fmt::Display,
        allowed: impl Into<String>,
    ) -> ExternalError {
        ExternalError::invalid(&self.path, field, at, value, allowed)
    }

    /// Checks the run against the scene named `scene` whose problem is `problem`, and reads a
    /// time above the horizon (within [`HORIZON_TOLERANCE`]) as the horizon: the first
    /// inconsistency is an error naming its field.
    pub fn check_against(&mut self, scene: &str, problem: &Problem1d) -> Result<(), ExternalError> {
        for (field, value) in [
            ("code.name", &self.code.name),
            ("code.version", &self.code.version),
            ("label", &self.label),
        ] {
            if value.trim().is_empty() {
                return Err(self.invalid(field, None, "\"\"", "a non-empty text"));
            }
        }
        if self.scene != scene {
            return Err(self.invalid(
                "scene",
                None,
                format!("{:?}", self.scene),
                format!("{scene:?}, the name of the scene given on the command line"),
            ));
        }
        if self.displacement.is_none()
            && self.contact_displacement.is_none()
            && self.lambda.is_none()
        {
            return Err(self.invalid(
                "displacement",
                None,
                "missing",
                "nodal displacements, or a contact trace (contact_displacement and/or lambda)",
            ));
        }
        self.check_declarations()?;
        self.check_mesh(problem)?;
        self.check_times(problem.horizon)?;
        if problem.far_end == EndCondition::Clamped {
            self.check_clamped_end()?;
        }
        self.check_contact_displacement()
    }

    /// A uniform P1 mesh of the bar `[0, L]`: node `i` within [`MESH_TOLERANCE`]`·L/NX` of
    /// `i L/NX`.
    fn check_mesh(&self, problem: &Problem1d) -> Result<(), ExternalError> {
        let nx = self.nx();
        let length = problem.length;
        if nx == 0 {
            return Err(self.invalid(
                "mesh.nodes",
                None,
                format!("{} node(s)", self.nodes.len()),
                "at least two nodes",
            ));
        }
        let h = length / nx as f64;
        for (i, &x) in self.nodes.iter().enumerate() {
            let expected = if i == nx { length } else { i as f64 * h };
            if (x - expected).abs() > MESH_TOLERANCE * h {
                return Err(self.invalid(
                    "mesh.nodes",
                    Some(format!("node {i}")),
                    x,
                    format!(
                        "the {} nodes of a uniform mesh of the scene's bar [0, {length}], \
                         ascending: node {i} at {expected} (L/NX = {h}) within a relative \
                         {MESH_TOLERANCE:e} of L/NX",
                        nx + 1
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `t_0 = 0 < t_1 < … < t_N`, `|t_N − T| ≤ HORIZON_TOLERANCE·T`; `lambda_time` and
    /// `energy_time` non-decreasing in `[0, T]`. Times above `T` within the tolerance are read
    /// as `T`.
    fn check_times(&mut self, horizon: f64) -> Result<(), ExternalError> {
        let origin = self.origin;
        if self.time.len() < 2 {
            return Err(self.invalid(
                "time",
                None,
                format!("{} sample(s)", self.time.len()),
                "at least two samples, from t = 0 to the horizon",
            ));
        }
        if self.time[0] != 0.0 {
            return Err(self.invalid(
                "time",
                Some(origin.at(0)),
                self.time[0],
                "0 for the first sample (the initial data)",
            ));
        }
        let last = self.time.len() - 1;
        if (self.time[last] - horizon).abs() > HORIZON_TOLERANCE * horizon {
            return Err(self.invalid(
                "time",
                Some(origin.at(last)),
                self.time[last],
                format!(
                    "the scene's horizon T = {horizon} for the last sample, within a relative \
                     {HORIZON_TOLERANCE:e}"
                ),
            ));
        }
        self.time[last] = self.time[last].min(horizon);
        for k in 1..self.time.len() {
            if self.time[k] <= self.time[k - 1] {
                return Err(self.invalid(
                    "time",
                    Some(origin.at(k)),
                    self.time[k],
                    format!(
                        "strictly increasing times: after {} (the previous sample)",
                        self.time[k - 1]
                    ),
                ));
            }
        }
        for (field, times, values) in [
            ("lambda_time", &self.lambda_time, self.lambda.is_some()),
            ("energy_time", &self.energy_time, self.energy.is_some()),
        ] {
            if times.is_some() && !values {
                let base = field.trim_end_matches("_time");
                return Err(self.invalid(
                    field,
                    None,
                    "given",
                    format!("only with {base} (the times its values approximate)"),
                ));
            }
        }
        let path = &self.path;
        for (field, times) in [
            ("lambda_time", &mut self.lambda_time),
            ("energy_time", &mut self.energy_time),
        ] {
            if let Some(times) = times {
                read_reported_times(path, origin, field, times, horizon)?;
            }
        }
        Ok(())
    }

    /// What the version allows: `scheme`, `mass`, `contact` and `energy_definition` only in
    /// version 2, where a reported `energy` needs its `energy_definition` and an
    /// `energy_definition` its `energy`.
    fn check_declarations(&self) -> Result<(), ExternalError> {
        let declared = [
            ("scheme", self.scheme.is_some()),
            ("mass", self.mass.is_some()),
            ("contact", self.contact.is_some()),
            ("energy_definition", self.energy_definition.is_some()),
        ];
        if self.contact.as_deref().is_some_and(|c| c.trim().is_empty()) {
            return Err(self.invalid("contact", None, "\"\"", "a non-empty text"));
        }
        match self.version {
            Version::One => match declared.iter().find(|(_, given)| *given) {
                Some((field, _)) => Err(self.invalid(
                    *field,
                    None,
                    "given",
                    format!("absent in {FORMAT:?}: it is read in {FORMAT_2:?}"),
                )),
                None => Ok(()),
            },
            Version::Two => match (&self.energy, self.energy_definition) {
                (Some(_), None) => Err(self.invalid(
                    "energy_definition",
                    None,
                    "missing",
                    format!(
                        "the definition of the reported energy, one of: {}",
                        EnergyDefinition::NAMES
                    ),
                )),
                (None, Some(_)) => Err(self.invalid(
                    "energy_definition",
                    None,
                    "given",
                    "only with energy (the definition of the code's reported energy)",
                )),
                _ => Ok(()),
            },
        }
    }

    /// The clamped end `x = L` at rest: its displacement and velocity within
    /// [`CLAMPED_TOLERANCE`] of 0 at every sample that has them.
    fn check_clamped_end(&self) -> Result<(), ExternalError> {
        let last = self.nodes.len() - 1;
        for (name, field) in [("u", &self.displacement), ("v", &self.velocity)] {
            for k in 0..self.samples() {
                let Some(value) = self.row(field, k).map(|row| row[last]) else {
                    continue;
                };
                if value.abs() > CLAMPED_TOLERANCE {
                    return Err(self.invalid(
                        format!("{name}{last}"),
                        Some(self.origin.at(k)),
                        value,
                        format!(
                            "0 within {CLAMPED_TOLERANCE:e}: the scene's bar is clamped at its \
                             last node"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// `contact_displacement` equal to the field's value at `x = 0` at every sample that has
    /// both.
    fn check_contact_displacement(&self) -> Result<(), ExternalError> {
        let Some(contact) = &self.contact_displacement else {
            return Ok(());
        };
        for (k, &c) in contact.iter().enumerate() {
            let Some(u0) = self.row(&self.displacement, k).map(|row| row[0]) else {
                continue;
            };
            if (c - u0).abs() > CONTACT_TOLERANCE * u0.abs().max(1.0) {
                return Err(self.invalid(
                    "contact_displacement",
                    Some(self.origin.at(k)),
                    c,
                    format!(
                        "the displacement field's value at x = 0 ({u0}) within \
                         {CONTACT_TOLERANCE:e} (relative, absolute below 1)"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Checks the times `times` at which the values of `field` are reported (`lambda_time`,
/// `energy_time`): non-decreasing, in `[0, T]` within [`HORIZON_TOLERANCE`]; a time above `T`
/// is read as `T`.
fn read_reported_times(
    path: &Path,
    origin: SampleOrigin,
    field: &str,
    times: &mut [f64],
    horizon: f64,
) -> Result<(), ExternalError> {
    let limit = horizon * (1.0 + HORIZON_TOLERANCE);
    let mut previous = 0.0;
    for (k, t) in times.iter_mut().enumerate() {
        if !(previous..=limit).contains(t) {
            return Err(ExternalError::invalid(
                path,
                field,
                Some(origin.at(k)),
                *t,
                format!(
                    "non-decreasing times in [0, T = {horizon}] (T within a relative \
                     {HORIZON_TOLERANCE:e}), here at least {previous}"
                ),
            ));
        }
        *t = t.min(horizon);
        previous = *t;
    }
    Ok(())
}
