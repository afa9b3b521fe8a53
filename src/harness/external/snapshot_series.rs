//! A box run's snapshots, one per time, from either kind of file that holds them: a ParaView
//! collection ([`super::pvd`]) or an XDMF file with its heavy data ([`super::xdmf`]).

use std::path::Path;

use super::error::ExternalError;
use super::nodal_snapshot::NodalSnapshot;
use super::pvd::{read_collection, read_snapshot, CollectionEntry};
use super::xdmf::XdmfSeries;

/// What the box reader takes as a series of snapshots, for its errors.
pub const SERIES_FILES: &str =
    ".pvd (a ParaView collection), .xdmf (XDMF with HDF5 heavy data) or .json (the format's box \
     form) for a box scene";

/// The snapshots of one run, in increasing time; each is read when it is asked for.
#[derive(Debug, Clone)]
pub enum SnapshotSeries {
    /// A ParaView collection: one grid file per time.
    Pvd(Vec<CollectionEntry>),
    /// An XDMF file: one geometry, the attributes of each time.
    Xdmf(XdmfSeries),
}

impl SnapshotSeries {
    /// Reads the series file `path`, by its extension (`.pvd` or `.xdmf`, any case); `None` for
    /// another extension.
    pub fn read(path: &Path) -> Option<Result<Self, ExternalError>> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("pvd") => Some(read_collection(path).map(Self::Pvd)),
            Some("xdmf") => Some(XdmfSeries::read(path).map(Self::Xdmf)),
            _ => None,
        }
    }

    /// The snapshots' times, increasing.
    pub fn times(&self) -> Vec<f64> {
        match self {
            Self::Pvd(entries) => entries.iter().map(|e| e.time).collect(),
            Self::Xdmf(series) => series.times(),
        }
    }

    /// Snapshot `n`, read now.
    pub fn snapshot(&self, n: usize) -> Result<NodalSnapshot, ExternalError> {
        match self {
            Self::Pvd(entries) => read_snapshot(&entries[n].file),
            Self::Xdmf(series) => series.snapshot(n),
        }
    }
}
