//! A run file of GetFEM's demo that could not be read ([`DemoRunError`]).

use std::path::PathBuf;

use thiserror::Error;

use crate::harness::files::input::{InputError, Shown};

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
