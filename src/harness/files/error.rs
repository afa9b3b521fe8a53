//! Errors of the harness: the engine's (its [`ParameterError`], with the check
//! [`require_positive`] that makes one, and its [`SolveError`]), plus the files it reads and
//! writes (scene files among them).

use std::fmt;
use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::engine::error as engine;
pub use crate::engine::error::{require_positive, ParameterError, SolveError};
pub use crate::harness::files::input::printable;
use crate::harness::files::input::{shown, InputError, JsonError, Shown};

/// Any error of a harness run or study.
#[derive(Debug, Error)]
pub enum Error {
    /// A parameter out of range.
    #[error(transparent)]
    Parameter(#[from] ParameterError),
    /// Time stepping failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// A box cannot be run over the ranks asked for.
    #[error(transparent)]
    Distributed(#[from] crate::engine::distributed::DecompositionError),
    /// A file could not be read or written.
    #[error("cannot {action} {}: {source}", Shown(path))]
    Io {
        /// `read` or `write`.
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// What the system reported.
        #[source]
        source: std::io::Error,
    },
    /// Data could not be encoded as JSON.
    #[error("cannot encode {what} as JSON: {source}")]
    Encode {
        /// What was being encoded (its file).
        what: String,
        /// What serde reported.
        #[source]
        source: serde_json::Error,
    },
    /// A JSON file is not what its reader expects.
    #[error("{} is not a valid file of its kind: {source}", Shown(path))]
    Decode {
        /// The file.
        path: PathBuf,
        /// What serde reported.
        #[source]
        source: serde_json::Error,
    },
    /// A figure could not be drawn.
    #[error(transparent)]
    Figure(#[from] FigureError),
    /// A run of GetFEM's demo could not be read.
    #[error(transparent)]
    DemoRun(#[from] DemoRunError),
    /// A VTK file could not be written.
    #[error("cannot write {}: {source}", Shown(path))]
    Vtk {
        /// The file.
        path: PathBuf,
        /// What vtkio reported.
        #[source]
        source: vtkio::Error,
    },
    /// A scene file could not be read or is not valid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A shard could not be run or shards could not be merged.
    #[error(transparent)]
    Shard(#[from] ShardError),
    /// A value in a file out of its range (a negative tolerance or error, a non-finite rate).
    #[error("{}: {field} = {value}; allowed: {allowed}", Shown(path))]
    OutOfRange {
        /// The file.
        path: PathBuf,
        /// The field, dotted (`tolerances.rate_abs`, `cases[2].norms.u_L2_H.errors[1]`).
        field: String,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The estimated cost is over a limit ([`crate::harness::study::budget`]).
    #[error(transparent)]
    Budget(#[from] BudgetError),
    /// An input file is missing, not a regular file or over its size limit.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A file to write exists and is not a regular file (a FIFO, a device, a directory).
    #[error(
        "{} is {found}; allowed: a regular file or a new name (nothing but a regular file is \
         replaced)",
        Shown(path)
    )]
    NotRegularOutput {
        /// The file.
        path: PathBuf,
        /// What it is.
        found: &'static str,
    },
}

impl From<JsonError> for Error {
    fn from(e: JsonError) -> Self {
        match e {
            JsonError::Input(e) => Error::Input(e),
            JsonError::Decode { path, source, .. } => Error::Decode { path, source },
        }
    }
}

impl Error {
    /// The error of encoding the content of `path`.
    pub fn encode(path: &Path) -> impl FnOnce(serde_json::Error) -> Self + '_ {
        move |source| Error::Encode {
            what: shown(path),
            source,
        }
    }

    /// The error of reading `path`.
    pub fn read(path: &Path) -> impl FnOnce(std::io::Error) -> Self + '_ {
        move |source| Error::Io {
            action: "read",
            path: path.to_path_buf(),
            source,
        }
    }

    /// The error of writing `path`.
    pub fn write(path: &Path) -> impl FnOnce(std::io::Error) -> Self + '_ {
        move |source| Error::Io {
            action: "write",
            path: path.to_path_buf(),
            source,
        }
    }
}

impl From<engine::Error> for Error {
    fn from(e: engine::Error) -> Self {
        match e {
            engine::Error::Parameter(p) => Error::Parameter(p),
            engine::Error::Solve(s) => Error::Solve(s),
        }
    }
}

/// A scene that could not be read or is not valid.
#[derive(Debug)]
pub enum SceneError {
    /// The file cannot be read, is not a regular file or is too large.
    Input(InputError),
    /// Malformed JSON, an unknown or missing field, or a value of the wrong type.
    Json {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde's message (names the field and, for unknown fields, the allowed ones).
        message: String,
    },
    /// A value out of range or inconsistent with the rest of the scene.
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// The field, dotted (`material.density`).
        field: String,
        /// The offending value.
        value: String,
        /// What is allowed.
        allowed: String,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Input(e) => e.fmt(f),
            SceneError::Json {
                path,
                line,
                column,
                message,
            } => write!(
                f,
                "scene file {} is not a valid scene (line {line}, column {column}): {message}",
                Shown(path)
            ),
            SceneError::Invalid {
                path,
                field,
                value,
                allowed,
            } => write!(
                f,
                "scene file {}: invalid {field} = {}; allowed: {}",
                Shown(path),
                printable(value),
                printable(allowed)
            ),
        }
    }
}

impl SceneError {
    /// Appends `detail` to what an [`SceneError::Invalid`] says is allowed.
    pub(crate) fn with_detail(self, detail: String) -> Self {
        match self {
            SceneError::Invalid {
                path,
                field,
                value,
                allowed,
            } => SceneError::Invalid {
                path,
                field,
                value,
                allowed: if allowed.is_empty() {
                    detail
                } else {
                    format!("{allowed} ({detail})")
                },
            },
            other => other,
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneError::Input(e) => Some(e),
            _ => None,
        }
    }
}

/// Why a figure could not be drawn.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum FigureError {
    /// The drawing library reported an error (its message).
    #[error("drawing failed: {0}")]
    Drawing(String),
    /// Nothing finite was left to draw.
    #[error("nothing to plot: {what}")]
    EmptyData {
        /// What was empty (the figure, panel or series).
        what: String,
    },
    /// Two inputs that describe the same runs disagree (e.g. an ensemble run at other levels
    /// than the study it is drawn with).
    #[error("inconsistent inputs: {what}")]
    Inconsistent {
        /// What disagrees with what.
        what: String,
    },
    /// Two sequences that pair up point by point have different lengths.
    #[error("{what}: {left} abscissae but {right} values")]
    LengthMismatch {
        /// Which series.
        what: String,
        /// Length of the abscissae (times, mesh sizes, seconds).
        left: usize,
        /// Length of the values.
        right: usize,
    },
}

/// A run file of GetFEM's 1D contact demo (`tests/data/getfem/*.json.gz`, read by
/// [`crate::harness::getfem`]) that could not be read or is not what its reader expects. Every
/// variant names the file; the field errors name the field (`params.beta`, `arrays.TT`).
#[derive(Debug, Error)]
pub enum DemoRunError {
    /// The file or directory cannot be read.
    #[error("cannot read GetFEM demo run {}: {source}", Shown(path))]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What the system reported.
        #[source]
        source: std::io::Error,
    },
    /// Not a regular file.
    #[error(transparent)]
    Input(InputError),
    /// The file, or the JSON it inflates to, is larger than the reader accepts.
    #[error("GetFEM demo run {}: the {what} exceeds {limit} bytes", Shown(path))]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// `compressed file` or `decompressed JSON`.
        what: &'static str,
        /// The limit in bytes.
        limit: u64,
    },
    /// The file is not valid gzip.
    #[error("GetFEM demo run {} is not valid gzip: {source}", Shown(path))]
    Gzip {
        /// The file.
        path: PathBuf,
        /// What the decoder reported.
        #[source]
        source: std::io::Error,
    },
    /// The JSON is malformed, a top-level section is missing, or an array holds something else
    /// than numbers and nulls (serde's message names the section or the array).
    #[error("GetFEM demo run {} is not a valid run file: {source}", Shown(path))]
    Json {
        /// The file.
        path: PathBuf,
        /// What serde reported.
        #[source]
        source: serde_json::Error,
    },
    /// A field is missing, of the wrong type or out of range, or an array has the wrong length.
    #[error(
        "GetFEM demo run {}: {field} is {found}; expected {expected}",
        Shown(path)
    )]
    Field {
        /// The file.
        path: PathBuf,
        /// The field, dotted (`params.mass_matrix_type`, `arrays.store_UL2`).
        field: String,
        /// What the file holds (`missing` when absent).
        found: String,
        /// What is allowed.
        expected: String,
    },
    /// A file name that does not follow the convention of `tests/data/getfem/README.md`.
    #[error(
        "{}: not a GetFEM demo run name \
         (getfem_v{{version}}_b{{beta}}_g{{gamma}}[_e{{e}}|_gP{{g}}|_gN{{g}}_tN{{theta}}][_lump]_m{{mass}}_nx{{NX}}[_k2].json.gz): {problem}",
        Shown(path)
    )]
    Name {
        /// The file.
        path: PathBuf,
        /// What does not fit.
        problem: String,
    },
}

/// What can go wrong when sharding a study or merging its shards (`crate::harness::study::shard`).
#[derive(Debug, Error)]
pub enum ShardError {
    /// The shards hold another number of results for a job list than the study's list has jobs.
    #[error(
        "the shards hold {shards} job results for job list {list} but the study has {study} jobs \
         in it: the shards are of another version of the study"
    )]
    JobCount {
        /// The list, from 1 in the order the study hands its lists.
        list: usize,
        /// Results in the shards for it.
        shards: usize,
        /// Jobs in the study's list.
        study: usize,
    },
    /// A command handed no result back from job lists run here or merged: a defect of the
    /// command, not of the shards.
    #[error("the command made nothing of its job lists' results (a defect: please report it)")]
    NoResult,
    /// The shards hold more job lists than the study hands its executor.
    #[error(
        "the shards hold {shards} job lists but the study has {study}: the shards are of \
         another version of the study"
    )]
    ListCount {
        /// Lists in the shards.
        shards: usize,
        /// Lists of the study.
        study: usize,
    },
    /// A result could not be encoded.
    #[error("cannot encode a job result: {0}")]
    Encode(String),
    /// A result could not be decoded.
    #[error("the result of job {index} in the shards is damaged: {why}")]
    Decode {
        /// The job's index.
        index: usize,
        /// What was wrong.
        why: String,
    },
    /// No shard file was given to merge.
    #[error("no shard file given: merge takes the n files of one sharded command")]
    NoShards,
    /// A file of another format.
    #[error(
        "{}: format {}, expected {expected:?} (a shard file of another version of signorini: \
         run the shards again with this one)",
        Shown(path),
        printable(&format!("{found:?}"))
    )]
    Format {
        /// The file.
        path: PathBuf,
        /// Its format.
        found: String,
        /// The format this version reads.
        expected: &'static str,
    },
    /// Two shards of different invocations.
    #[error(
        "{} and {} are shards of different invocations (their {field} differ): merge the \
         shards of one command line",
        Shown(first),
        Shown(other)
    )]
    Mismatch {
        /// The field that differs.
        field: &'static str,
        /// The first shard.
        first: PathBuf,
        /// The other shard.
        other: PathBuf,
    },
    /// A shard number out of `1..=n`.
    #[error("{}: shard {k} of {n} is out of range (k from 1 to n)", Shown(path))]
    ShardNumber {
        /// The file.
        path: PathBuf,
        /// Its `k`.
        k: usize,
        /// Its `n`.
        n: usize,
    },
    /// A shard given more than once.
    #[error("shard {k}/{n} is given more than once: {}", path_list(paths))]
    Duplicate {
        /// The shard's `k`.
        k: usize,
        /// The number of shards.
        n: usize,
        /// The files holding it.
        paths: Vec<PathBuf>,
    },
    /// Shards missing.
    #[error(
        "missing shard{} {} (all n = {n} shards of the command are needed)",
        if missing.len() == 1 { "" } else { "s" },
        ranges(missing, *n)
    )]
    Missing {
        /// The `k` of each missing shard.
        missing: Vec<usize>,
        /// The number of shards.
        n: usize,
    },
    /// A job index out of the list or given twice.
    #[error(
        "{}: job {index} is out of the list of {jobs} jobs or in another shard too",
        Shown(path)
    )]
    JobIndex {
        /// The file.
        path: PathBuf,
        /// The index.
        index: usize,
        /// The number of jobs.
        jobs: usize,
    },
    /// A shard file whose content is not what its shard wrote (its checksum differs).
    #[error(
        "{}: its checksum does not match its content: the file was changed or damaged after \
         its shard wrote it; run that shard again",
        Shown(path)
    )]
    Checksum {
        /// The file.
        path: PathBuf,
    },
    /// A shard file whose job lists do not make up its whole list.
    #[error(
        "{}: its job lists hold {listed} jobs but jobs = {jobs}: the file is not a shard's",
        Shown(path)
    )]
    Lists {
        /// The file.
        path: PathBuf,
        /// The jobs its lists hold.
        listed: usize,
        /// Its `jobs`.
        jobs: usize,
    },
    /// A count in a shard file over what a merge accepts.
    #[error("{}: {field} = {value}; allowed: at most {max}", Shown(path))]
    TooMany {
        /// The file.
        path: PathBuf,
        /// The field (`n`, `jobs`).
        field: &'static str,
        /// Its value.
        value: usize,
        /// The largest accepted.
        max: usize,
    },
    /// A job result whose values are not a result's (non-finite, or out of their range).
    #[error("the result of job {index} in the shards is out of range: {why}")]
    OutOfRange {
        /// The job's index.
        index: usize,
        /// The value and its range.
        why: String,
    },
    /// A job no shard holds.
    #[error("no shard holds job {index}: the shard files are incomplete")]
    MissingJob {
        /// The index.
        index: usize,
    },
    /// The inputs differ from those the shards ran.
    #[error(
        "the shards ran {command} on other inputs than the files here ({}): a scene file \
         changed since, or the merge runs in another directory than the shards",
        inputs.iter().map(|p| shown(p)).collect::<Vec<_>>().join(", ")
    )]
    InputsChanged {
        /// The command.
        command: String,
        /// Its input files.
        inputs: Vec<PathBuf>,
    },
}

impl ShardError {
    /// Whether the error is the user's to fix in the arguments (exit code 2): shard files that
    /// do not make one complete invocation.
    pub fn is_usage(&self) -> bool {
        !matches!(self, Self::Encode(_) | Self::NoResult)
    }
}

/// The shard numbers `ks` (ascending) of `n` as ranges, `2/8, 4/8–6/8`, the first ten ranges
/// and how many more: a message stays one short line whatever `n` is.
fn ranges(ks: &[usize], n: usize) -> String {
    const SHOWN: usize = 10;
    let mut spans: Vec<(usize, usize)> = Vec::new();
    for &k in ks {
        match spans.last_mut() {
            Some((_, last)) if *last + 1 == k => *last = k,
            _ => spans.push((k, k)),
        }
    }
    let mut text: Vec<String> = spans
        .iter()
        .take(SHOWN)
        .map(|&(a, b)| {
            if a == b {
                format!("{a}/{n}")
            } else {
                format!("{a}/{n}–{b}/{n}")
            }
        })
        .collect();
    if spans.len() > SHOWN {
        text.push(format!("and {} more ranges", spans.len() - SHOWN));
    }
    text.join(", ")
}

/// `paths`, separated by commas.
fn path_list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| shown(p))
        .collect::<Vec<_>>()
        .join(", ")
}

/// An estimate over a limit.
#[derive(Debug, Clone, PartialEq)]
pub enum BudgetError {
    /// The estimate of `resource` exceeds its limit.
    OverLimit {
        /// What is estimated (`memory`, `files written`, `work`).
        resource: &'static str,
        /// The estimate, with its unit.
        estimate: String,
        /// The limit, with its unit and where it comes from.
        limit: String,
        /// The option that raises it.
        option: &'static str,
    },
}

impl fmt::Display for BudgetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BudgetError::OverLimit {
                resource,
                estimate,
                limit,
                option,
            } => write!(
                f,
                "refused before starting: the estimated {resource} is {estimate}, over the \
                 limit of {limit}; use fewer elements, steps or output times, or raise the \
                 limit with {option}"
            ),
        }
    }
}

impl std::error::Error for BudgetError {}
