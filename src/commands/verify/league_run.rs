//! `signorini league` below the command line: every `<dir>/<entry>/verify.json` read (as
//! `signorini verify --out <dir>/<entry>` writes it), the league of them built by its report
//! section ([`League::of`]) and written, `league.md` and `league.json`, into a staged `--out`.

use std::path::{Component, Path, PathBuf};

use crate::commands::command_error::CommandError;
use crate::harness::external::ExternalError;
use crate::harness::files::artifacts::{write_atomic, write_json};
use crate::harness::files::input::{read_json, Limit};
use crate::harness::files::manifest::Manifest;
use crate::harness::files::output_dir::{Replace, StagedDir};
use crate::studies::elastic_study::external::JudgedVerification;
use crate::studies::league::{render, League};

/// The file each entry directory holds.
const VERIFY_JSON: &str = "verify.json";

/// A verify.json, as read (64 MiB at most).
const VERIFY_FILE: Limit = Limit {
    what: "verification",
    max_bytes: 64 << 20,
};

/// Reads every `<dir>/<entry>/verify.json` (entries by name); a directory that cannot be read
/// or holds none is refused, saying how to write one. An entry whose `verify.json` is not a
/// regular file, or whose series are not what `verify` wrote ([`Series::inconsistency`]: a rate
/// that is not the fit of its errors, a negative error, …) is refused, naming the file and the
/// field; one edited since `verify` wrote it (its directory's manifest holds another SHA-256,
/// or there is none) is warned about.
///
/// [`Series::inconsistency`]: crate::harness::external::verify::Series::inconsistency
fn read_entries(dir: &Path) -> Result<Vec<(String, JudgedVerification)>, CommandError> {
    let listing = std::fs::read_dir(dir).map_err(|e| {
        CommandError::Refused(format!(
            "cannot read the league's directory {}: {e}",
            dir.display()
        ))
    })?;
    let mut files: Vec<(String, PathBuf)> = listing
        .filter_map(Result::ok)
        .map(|e| (e.file_name().to_string_lossy().into_owned(), e.path()))
        .map(|(name, path)| (name, path.join(VERIFY_JSON)))
        .filter(|(_, file)| std::fs::symlink_metadata(file).is_ok())
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(CommandError::Refused(format!(
            "{} holds no <entry>/{VERIFY_JSON}: write one with `signorini verify SCENE RUN... \
             --out {}/<entry>`",
            dir.display(),
            dir.display()
        )));
    }
    files
        .into_iter()
        .map(|(name, file)| {
            let v: JudgedVerification = read_json(&file, VERIFY_FILE)
                .map_err(|e| CommandError::from(ExternalError::of_json(&file, e)))?;
            for (k, series) in v.series.iter().enumerate() {
                if let Some((field, value, allowed)) = series.inconsistency() {
                    let field = format!("series[{k}].{field}");
                    return Err(ExternalError::invalid(&file, field, None, value, allowed).into());
                }
            }
            let entry = file.parent().unwrap_or(dir);
            if !Manifest::of(entry).owns(entry, VERIFY_JSON) {
                eprintln!(
                    "warning: {}: not as `signorini verify` wrote it (its directory's manifest \
                     does not hold this content): tabulated from its numbers, which are checked \
                     for consistency, not for where they came from",
                    file.display()
                );
            }
            Ok((name, v))
        })
        .collect()
}

/// Reads the league under `dir` and writes `league.md` and `league.json` into `out`; tells
/// `say` what it wrote.
pub fn write_league(dir: &Path, out: &Path, say: &mut dyn FnMut(&str)) -> Result<(), CommandError> {
    let league = League::of(&read_entries(dir)?);
    let entries = link_from(out, dir);
    let staged = StagedDir::begin("--out", out, Replace::Files)?;
    write_json(&staged.path().join("league.json"), &league)?;
    write_atomic(
        &staged.path().join("league.md"),
        render(&league, &entries).as_bytes(),
    )?;
    staged.commit()?;
    let rows: usize = league.entries.iter().map(|e| e.rows.len()).sum();
    say(&format!(
        "wrote {}/league.md and league.json ({} entries, {rows} series)",
        out.display(),
        league.entries.len()
    ));
    Ok(())
}

/// The directory `to` as the prefix of a link from a page in the directory `from`: the relative
/// path between the two once both are absolute and resolved (`from` need not exist yet: its
/// nearest existing ancestor is resolved), with a trailing `/`, empty when they are one
/// directory; `to` as given when one cannot be resolved.
fn link_from(from: &Path, to: &Path) -> String {
    let resolved = |p: &Path| -> Option<PathBuf> {
        let absolute = std::path::absolute(p).ok()?;
        let existing = absolute.ancestors().find(|a| a.exists())?;
        let rest = absolute.strip_prefix(existing).ok()?;
        Some(existing.canonicalize().ok()?.join(rest))
    };
    let (Some(from), Some(to_resolved)) = (resolved(from), resolved(to)) else {
        return format!("{}/", to.display());
    };
    let common = from
        .components()
        .zip(to_resolved.components())
        .take_while(|(a, b)| a == b)
        .count();
    let up = from.components().count() - common;
    let link: PathBuf = std::iter::repeat_n(Component::ParentDir, up)
        .chain(to_resolved.components().skip(common))
        .collect();
    if link.as_os_str().is_empty() {
        String::new()
    } else {
        format!("{}/", link.display())
    }
}
