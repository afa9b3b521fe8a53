//! The JSON form of an external run: the file's serde types (unknown fields refused) and their
//! conversion into an [`ExternalRun`], with every number checked finite and every sample checked
//! to carry the same fields, each of the mesh's length.

use std::path::Path;

use serde::{Deserialize, Deserializer};

use super::error::ExternalError;
use super::format::{check_size, Code, ExternalRun, SampleOrigin, FORMAT, MAX_VALUES};

/// A number as written; `null` (how JSON writers store NaN and infinity) is kept as NaN so that
/// the conversion can refuse it by name.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(from = "Option<f64>")]
struct Number(f64);

impl From<Option<f64>> for Number {
    fn from(v: Option<f64>) -> Self {
        Number(v.unwrap_or(f64::NAN))
    }
}

/// An optional field that is present as soon as its key is, even as `null`.
fn present<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

/// A run file as written.
#[derive(Debug, Deserialize)]
#[serde(rename = "ExternalRun", deny_unknown_fields)]
struct RunFile {
    /// [`FORMAT`].
    format: String,
    /// The scene's name.
    scene: String,
    /// The code and its version.
    code: Code,
    /// The configuration's label.
    label: String,
    /// The mesh.
    mesh: MeshFile,
    /// One entry per time sample.
    samples: Vec<SampleFile>,
}

/// The mesh as written.
#[derive(Debug, Deserialize)]
#[serde(rename = "Mesh", deny_unknown_fields)]
struct MeshFile {
    /// Node positions, ascending.
    nodes: Vec<Number>,
}

/// One sample as written.
#[derive(Debug, Deserialize)]
#[serde(rename = "Sample", deny_unknown_fields)]
struct SampleFile {
    time: Number,
    #[serde(default, deserialize_with = "present")]
    displacement: Option<Vec<Number>>,
    #[serde(default, deserialize_with = "present")]
    velocity: Option<Vec<Number>>,
    #[serde(default, deserialize_with = "present")]
    lambda: Option<Number>,
    #[serde(default, deserialize_with = "present")]
    lambda_time: Option<Number>,
    #[serde(default, deserialize_with = "present")]
    contact_displacement: Option<Number>,
    #[serde(default, deserialize_with = "present")]
    energy: Option<Number>,
    #[serde(default, deserialize_with = "present")]
    energy_time: Option<Number>,
}

/// `v` when finite; otherwise the error naming `field` at `at`.
fn finite(
    path: &Path,
    field: &str,
    at: impl Fn() -> String,
    v: Number,
) -> Result<f64, ExternalError> {
    if v.0.is_finite() {
        Ok(v.0)
    } else {
        Err(ExternalError::invalid(
            path,
            field,
            Some(at()),
            "null (not a finite number)",
            "a finite number: a run that went non-finite has no error norm",
        ))
    }
}

/// Reads the JSON run file `path` (at most [`super::format::MAX_FILE_BYTES`]).
pub fn read(path: &Path) -> Result<ExternalRun, ExternalError> {
    check_size(path)?;
    let text = std::fs::read_to_string(path).map_err(|source| ExternalError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let file: RunFile = serde_json::from_str(&text).map_err(|e| ExternalError::Json {
        path: path.to_path_buf(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    drop(text);
    convert(path, file)
}

/// The per-sample scalar fields: their names and how to get each from a sample.
type Scalar = (&'static str, fn(&SampleFile) -> Option<Number>);

const SCALARS: [Scalar; 5] = [
    ("lambda", |s| s.lambda),
    ("lambda_time", |s| s.lambda_time),
    ("contact_displacement", |s| s.contact_displacement),
    ("energy", |s| s.energy),
    ("energy_time", |s| s.energy_time),
];

fn convert(path: &Path, file: RunFile) -> Result<ExternalRun, ExternalError> {
    if file.format != FORMAT {
        return Err(ExternalError::invalid(
            path,
            "format",
            None,
            format!("{:?}", file.format),
            format!("{FORMAT:?}"),
        ));
    }
    let nodes = file
        .mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(i, &x)| finite(path, "mesh.nodes", || format!("node {i}"), x))
        .collect::<Result<Vec<f64>, _>>()?;
    let n = nodes.len();
    let samples = &file.samples;
    let first = samples.first();
    let has_u = first.is_some_and(|s| s.displacement.is_some());
    let has_v = first.is_some_and(|s| s.velocity.is_some());
    let per_sample = 1 + n * (usize::from(has_u) + usize::from(has_v)) + SCALARS.len();
    if samples.len().saturating_mul(per_sample) > MAX_VALUES {
        return Err(ExternalError::invalid(
            path,
            "samples",
            None,
            format!("{} samples of {per_sample} values", samples.len()),
            format!("at most {MAX_VALUES} values in one file"),
        ));
    }
    let at = |k: usize| SampleOrigin::Json.at(k);
    let mut time = Vec::with_capacity(samples.len());
    let (mut u, mut v) = (Vec::new(), Vec::new());
    let mut scalars = SCALARS.map(|(_, get)| {
        first
            .and_then(get)
            .map(|_| Vec::with_capacity(samples.len()))
    });
    for (k, s) in samples.iter().enumerate() {
        time.push(finite(path, "time", || at(k), s.time)?);
        push_row(
            path,
            "displacement",
            k,
            has_u,
            s.displacement.as_deref(),
            n,
            &mut u,
        )?;
        push_row(path, "velocity", k, has_v, s.velocity.as_deref(), n, &mut v)?;
        for ((name, get), out) in SCALARS.iter().zip(&mut scalars) {
            match (get(s), out) {
                (Some(x), Some(out)) => out.push(finite(path, name, || at(k), x)?),
                (None, None) => {}
                (x, _) => return Err(inconsistent(path, name, k, x.is_some())),
            }
        }
    }
    let [lambda, lambda_time, contact_displacement, energy, energy_time] = scalars;
    Ok(ExternalRun {
        path: path.to_path_buf(),
        origin: SampleOrigin::Json,
        scene: file.scene,
        code: file.code,
        label: file.label,
        nodes,
        time,
        displacement: has_u.then_some(u),
        velocity: has_v.then_some(v),
        lambda,
        lambda_time,
        contact_displacement,
        energy,
        energy_time,
    })
}

/// Appends sample `k`'s nodal values `row` of `field` to `out`: present exactly when sample 0's
/// are (`expected`), `n` of them, each finite.
fn push_row(
    path: &Path,
    field: &str,
    k: usize,
    expected: bool,
    row: Option<&[Number]>,
    n: usize,
    out: &mut Vec<f64>,
) -> Result<(), ExternalError> {
    match (row, expected) {
        (None, false) => Ok(()),
        (Some(row), true) if row.len() == n => {
            for (i, &x) in row.iter().enumerate() {
                let at = || format!("{}, node {i}", SampleOrigin::Json.at(k));
                out.push(finite(path, field, at, x)?);
            }
            Ok(())
        }
        (Some(row), true) => Err(ExternalError::invalid(
            path,
            field,
            Some(SampleOrigin::Json.at(k)),
            format!("{} values", row.len()),
            format!("one value per mesh node ({n})"),
        )),
        (row, _) => Err(inconsistent(path, field, k, row.is_some())),
    }
}

/// A field that sample `k` has and sample 0 lacks, or the other way round.
fn inconsistent(path: &Path, field: &str, k: usize, here: bool) -> ExternalError {
    let (value, allowed) = if here {
        (
            "given",
            "absent, as in samples[0]: every sample carries the same fields",
        )
    } else {
        (
            "missing",
            "given, as in samples[0]: every sample carries the same fields",
        )
    };
    ExternalError::invalid(path, field, Some(SampleOrigin::Json.at(k)), value, allowed)
}
