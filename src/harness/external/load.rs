//! Reading a run file of either form, chosen by its extension, and checking it against the
//! scene it claims to solve.

use std::path::Path;

use super::error::ExternalError;
use super::format::ExternalRun;
use super::{csv, json};
use crate::engine::problem::Problem1d;

/// Reads the run file `path` (`.json` or `.csv`, any case) and checks it against the scene
/// named `scene` whose problem is `problem` ([`ExternalRun::check_against`]).
pub fn load(path: &Path, scene: &str, problem: &Problem1d) -> Result<ExternalRun, ExternalError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let mut run = match extension.as_deref() {
        Some("json") => json::read(path)?,
        Some("csv") => csv::read(path)?,
        other => {
            return Err(ExternalError::invalid(
                path,
                "file name",
                None,
                format!("extension {:?}", other.unwrap_or("")),
                ".json or .csv (the two forms of the format)",
            ))
        }
    };
    run.check_against(scene, problem)?;
    Ok(run)
}
