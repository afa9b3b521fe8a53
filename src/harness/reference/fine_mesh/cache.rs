//! The cache of a fine-mesh reference ([`super::fine_run::FineReference`]): its key and its
//! files.
//!
//! The cache is two files under a directory: `<stem>.json` (the [`ReferenceKey`], the scalar
//! histories, the check) and `<stem>.bin` (the projections, little-endian `f64`, level after
//! level in [`LevelProjections::values`] order). The stem names the key
//! ([`ReferenceKey::stem`]), so references of different parameters live side by side and none
//! evicts another. A cache is used only when its key equals the key of the reference asked for,
//! field by field; otherwise it is recomputed. A [`ReferenceCache`] says whether the run may
//! write the directory.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::harness::files::artifacts::write_atomic;
use crate::harness::files::error::Error;
use crate::harness::files::input::{self, InputError, JsonError, Limit, LARGEST_VALUE};
use crate::harness::files::manifest::hex;
use crate::harness::problem::{Conventions, MassVariant, Scheme};
use crate::harness::run::elastic::BoxProblem;
use crate::harness::run::nested_comparison::projection::LevelProjections;

/// Layout version of the cache files; bump it when their content changes meaning (2: the
/// projections on the fitted levels and the lockstep check replace the displacement samples;
/// 3: the checksum).
const CACHE_FORMAT: u32 = 3;

/// A cache's `.json` file, as [`input`] reads it (its histories have a few thousand samples).
const REFERENCE_JSON: Limit = Limit {
    what: "cached reference",
    max_bytes: 64 * 1024 * 1024,
};

/// Everything that determines a reference run: the cache is valid only for an equal key.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceKey {
    /// Box lengths.
    pub lengths: Vec<f64>,
    /// `ρ`.
    pub density: f64,
    /// Lamé `λ`.
    pub lame_lambda: f64,
    /// Lamé `μ`.
    pub lame_mu: f64,
    /// Distance to the obstacle.
    pub obstacle_gap: Option<f64>,
    /// Uniform initial axial displacement.
    pub initial_displacement: f64,
    /// Uniform initial axial velocity.
    pub initial_velocity: f64,
    /// Horizon `T`.
    pub horizon: f64,
    /// The contact treatment's name.
    pub contact: String,
    /// Elements along the axis.
    pub n_axis: usize,
    /// `Δx / Δt`.
    pub ratio: f64,
    /// Scheme name.
    pub scheme: String,
    /// Mass variant name.
    pub mass: String,
    /// The schemes' conventions; absent when they are the harness's ([`Conventions::HARNESS`]),
    /// so the keys and cache names of the harness's references do not depend on the field.
    #[serde(default = "harness_conventions", skip_serializing_if = "is_harness")]
    pub conventions: Conventions,
    /// Fine steps per stored sample.
    pub sample_every: usize,
    /// The fitted levels the reference is projected on.
    pub levels: Vec<usize>,
    /// Cache layout version.
    pub format: u32,
    /// The crate version that computed it.
    pub signorini_version: String,
}

fn harness_conventions() -> Conventions {
    Conventions::HARNESS
}

fn is_harness(conventions: &Conventions) -> bool {
    *conventions == Conventions::HARNESS
}

impl ReferenceKey {
    /// The key of a reference run of `problem` on `n_axis` elements along the axis, projected on
    /// the fitted `levels`, with its scalar histories every `sample_every` fine steps.
    pub fn new(
        problem: &BoxProblem,
        conventions: Conventions,
        n_axis: usize,
        ratio: f64,
        case: (Scheme, MassVariant),
        levels: &[usize],
        sample_every: usize,
    ) -> Self {
        let (scheme, mass) = case;
        Self {
            lengths: problem.lengths.clone(),
            density: problem.elasticity.density,
            lame_lambda: problem.elasticity.lame_lambda,
            lame_mu: problem.elasticity.lame_mu,
            obstacle_gap: problem.obstacle_gap,
            initial_displacement: problem.initial_displacement,
            initial_velocity: problem.initial_velocity,
            horizon: problem.horizon,
            contact: problem.contact.name(),
            n_axis,
            ratio,
            scheme: scheme.name(),
            mass: mass.name().to_string(),
            conventions,
            sample_every,
            levels: levels.to_vec(),
            format: CACHE_FORMAT,
            signorini_version: env!("CARGO_PKG_VERSION").to_string(),
        }
    }

    /// The cache file stem of this key: `reference-<d>d-<fingerprint>`, the fingerprint the
    /// 64-bit FNV-1a hash of the key's JSON (stable across runs, platforms and Rust versions),
    /// e.g. `reference-3d-5be0c1a29d3f4e77`.
    pub fn stem(&self) -> String {
        let text = serde_json::to_string(self).unwrap_or_default();
        let fingerprint = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        });
        format!("reference-{}d-{fingerprint:016x}", self.lengths.len())
    }

    /// The fields whose values differ from `other`'s, a field written by one key only (the
    /// conventions, absent when they are the harness's) included: empty when the keys are
    /// equal.
    pub fn differences(&self, other: &ReferenceKey) -> Vec<String> {
        let (Ok(serde_json::Value::Object(wanted)), Ok(serde_json::Value::Object(cached))) =
            (serde_json::to_value(self), serde_json::to_value(other))
        else {
            return vec!["(key not serialisable)".to_string()];
        };
        let fields: std::collections::BTreeSet<&String> =
            wanted.keys().chain(cached.keys()).collect();
        let shown =
            |v: Option<&serde_json::Value>| v.map_or("absent".to_string(), |v| v.to_string());
        fields
            .into_iter()
            .filter(|k| wanted.get(*k) != cached.get(*k))
            .map(|k| {
                format!(
                    "{k}: cached {}, wanted {}",
                    shown(cached.get(k)),
                    shown(wanted.get(k))
                )
            })
            .collect()
    }
}

/// The scalar part of a reference (the `.json` cache file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceHistories {
    /// The parameters.
    pub key: ReferenceKey,
    /// Unknowns per sample.
    pub dofs: usize,
    /// Fine steps of the run.
    pub steps: usize,
    /// Fine `Δt`.
    pub dt: f64,
    /// Wall-clock time of the run, seconds.
    pub seconds: f64,
    /// Sample times `t_k`.
    pub time: Vec<f64>,
    /// `E_h(t_k)` (eq. 6).
    pub energy: Vec<f64>,
    /// `Σ_i λ_i(t_k)`.
    pub total_force: Vec<f64>,
    /// Axial displacement of the contact-face node nearest the centre.
    pub centre_displacement: Vec<f64>,
    /// Multiplier of that node.
    pub centre_multiplier: Vec<f64>,
    /// The layout of the projections in the `.bin` file, coarsest level first.
    pub projections: Vec<ProjectionLayout>,
    /// The reference case one level coarser, compared with the reference.
    pub check: CheckOutcome,
    /// SHA-256 of this file's compact JSON with this field empty followed by the `.bin` file's
    /// bytes ([`save`]): a cache changed since it was written is stale.
    #[serde(default)]
    pub checksum: String,
}

impl ReferenceHistories {
    /// The first value that is not finite, named; `None` when all are.
    fn non_finite(&self) -> Option<String> {
        let series: [(&str, &[f64]); 5] = [
            ("time", &self.time),
            ("energy", &self.energy),
            ("total_force", &self.total_force),
            ("centre_displacement", &self.centre_displacement),
            ("centre_multiplier", &self.centre_multiplier),
        ];
        let scalars = [("dt", self.dt)]
            .into_iter()
            .chain(self.check.distance.iter().map(|(k, d)| (k.as_str(), *d)));
        series
            .iter()
            .find_map(|(name, v)| {
                v.iter()
                    .position(|x| !x.is_finite())
                    .map(|k| format!("{name}[{k}] = {} is not finite", v[k]))
            })
            .or_else(|| {
                scalars
                    .filter(|(_, x)| !x.is_finite())
                    .map(|(name, x)| format!("{name} = {x} is not finite"))
                    .next()
            })
    }

    /// What makes the histories impossible for a run, named; `None` when nothing does: a time
    /// step that is not positive, steps that do not reach the horizon, samples that do not run
    /// from 0 to the horizon or do not increase, samples that are not one per step of the finest
    /// projected level (as many as its projections, evenly spaced), a history whose length is
    /// not the times', or a value beyond [`LARGEST_VALUE`] in magnitude.
    fn impossible(&self) -> Option<String> {
        if self.dt <= 0.0 {
            return Some(format!("dt = {} is not positive", self.dt));
        }
        let horizon = self.key.horizon;
        let off = |t: f64| (t - horizon).abs() > 1e-9 * horizon.abs().max(1.0);
        if off(self.dt * self.steps as f64) {
            return Some(format!(
                "dt × steps = {} × {} is not the horizon {horizon}",
                self.dt, self.steps
            ));
        }
        match (self.time.first(), self.time.last()) {
            (Some(&first), Some(&last)) if first == 0.0 && !off(last) => {}
            (Some(first), Some(last)) => {
                return Some(format!(
                    "the samples run from {first} to {last}, not from 0 to the horizon {horizon}"
                ))
            }
            _ => return Some("no samples".to_string()),
        }
        if let Some(k) = self.time.windows(2).position(|w| w[1] <= w[0]) {
            return Some(format!(
                "time[{}] = {} does not follow time[{k}] = {}",
                k + 1,
                self.time[k + 1],
                self.time[k]
            ));
        }
        let finest = self.projections.iter().max_by_key(|p| p.level);
        if let Some(p) = finest.filter(|p| p.samples != self.time.len()) {
            return Some(format!(
                "time has {} samples where level {}, the finest projected, has {} steps",
                self.time.len(),
                p.level,
                p.samples.saturating_sub(1)
            ));
        }
        let spacing = horizon / (self.time.len() - 1).max(1) as f64;
        if let Some(k) = (0..self.time.len())
            .find(|&k| (self.time[k] - k as f64 * spacing).abs() > 1e-9 * horizon.abs().max(1.0))
        {
            return Some(format!(
                "time[{k}] = {} is not step {k} of the finest projected level, {}",
                self.time[k],
                k as f64 * spacing
            ));
        }
        let series: [(&str, &[f64]); 4] = [
            ("energy", &self.energy),
            ("total_force", &self.total_force),
            ("centre_displacement", &self.centre_displacement),
            ("centre_multiplier", &self.centre_multiplier),
        ];
        if let Some((name, v)) = series.iter().find(|(_, v)| v.len() != self.time.len()) {
            return Some(format!(
                "{name} has {} samples where time has {}",
                v.len(),
                self.time.len()
            ));
        }
        series.iter().find_map(|(name, v)| {
            v.iter()
                .position(|x| x.abs() > LARGEST_VALUE)
                .map(|k| format!("{name}[{k}] = {:e} is beyond {LARGEST_VALUE:e}", v[k]))
        })
    }

    /// The SHA-256 state of this file's compact JSON with `checksum` empty, to be completed
    /// with the `.bin` file's bytes.
    fn digest(&self) -> Result<Sha256, serde_json::Error> {
        let blank = ReferenceHistories {
            checksum: String::new(),
            ..self.clone()
        };
        let mut digest = Sha256::new();
        digest.update(serde_json::to_string(&blank)?.as_bytes());
        Ok(digest)
    }
}

/// Where one level's projections are in the `.bin` file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProjectionLayout {
    /// Elements along the axis.
    pub level: usize,
    /// Unknowns of the level.
    pub dofs: usize,
    /// Steps recorded.
    pub samples: usize,
}

/// The run of the reference case one level coarser than the reference, and its distance to it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckOutcome {
    /// Elements along the axis (half the reference's).
    pub level: usize,
    /// Unknowns.
    pub dofs: usize,
    /// Steps.
    pub steps: usize,
    /// Norm key → distance to the reference over the common samples.
    pub distance: BTreeMap<String, f64>,
}

/// The cache file paths `<dir>/<stem>.json` and `<dir>/<stem>.bin`.
pub fn cache_paths(dir: &Path, stem: &str) -> (PathBuf, PathBuf) {
    (
        dir.join(format!("{stem}.json")),
        dir.join(format!("{stem}.bin")),
    )
}

/// Writes the cache (each file atomically; the binary first, so a `.json` never describes
/// a missing or partial `.bin`), the `.json` with the checksum of both.
pub fn save(
    (histories, projections): (&ReferenceHistories, &[LevelProjections]),
    dir: &Path,
    stem: &str,
) -> Result<(), Error> {
    let (json, bin) = cache_paths(dir, stem);
    let bytes: Vec<u8> = projections
        .iter()
        .flat_map(LevelProjections::values)
        .flat_map(f64::to_le_bytes)
        .collect();
    write_atomic(&bin, &bytes)?;
    let mut digest = histories.digest().map_err(Error::encode(&json))?;
    digest.update(&bytes);
    let histories = ReferenceHistories {
        checksum: hex(&digest.finalize()),
        ..histories.clone()
    };
    let text = serde_json::to_string(&histories).map_err(Error::encode(&json))?;
    write_atomic(&json, text.as_bytes())
}

/// Reads the cache if it exists and its key equals `key`: stale when the key differs, the
/// `.bin` file has another size than its layout says, the checksum does not match or a
/// value is not finite. A file that is not a regular one is an error.
pub fn load(dir: &Path, stem: &str, key: &ReferenceKey) -> Result<CacheLookup, Error> {
    let (json, bin) = cache_paths(dir, stem);
    let stale = |why: String| Ok(CacheLookup::Stale(vec![why]));
    let histories: ReferenceHistories = match input::read_json(&json, REFERENCE_JSON) {
        Ok(h) => h,
        Err(JsonError::Input(InputError::Io { source, .. }))
            if source.kind() == std::io::ErrorKind::NotFound =>
        {
            return Ok(CacheLookup::Missing)
        }
        Err(JsonError::Input(e @ InputError::NotRegular { .. })) => return Err(e.into()),
        Err(e) => return stale(format!("unreadable: {e}")),
    };
    let differences = key.differences(&histories.key);
    if !differences.is_empty() {
        return Ok(CacheLookup::Stale(differences));
    }
    if let Some(why) = histories.non_finite().or_else(|| histories.impossible()) {
        return stale(format!("{}: {why}", json.display()));
    }
    let expected = histories.projections.iter().try_fold(0_u64, |sum, l| {
        let values = LevelProjections::value_count(l.dofs, l.samples)?;
        sum.checked_add(u64::try_from(values).ok()?.checked_mul(8)?)
    });
    let Some(expected) = expected else {
        return stale(format!("{}: its layout overflows", json.display()));
    };
    let limit = Limit {
        what: "cached reference",
        max_bytes: expected,
    };
    let mut file = match input::open(&bin, limit) {
        Ok(file) if file.size() == expected => file,
        Ok(file) => {
            return stale(format!(
                "{} has {} bytes, expected {expected}",
                bin.display(),
                file.size()
            ))
        }
        Err(e @ InputError::NotRegular { .. }) => return Err(e.into()),
        Err(e) => return stale(e.to_string()),
    };
    let mut digest = histories.digest().map_err(Error::encode(&json))?;
    let mut block = vec![0_u8; 1 << 16];
    let mut next = |values: &mut [f64]| -> Option<()> {
        for chunk in values.chunks_mut(block.len() / 8) {
            let bytes = &mut block[..chunk.len() * 8];
            file.read_exact(bytes).ok()?;
            digest.update(&*bytes);
            for (x, b) in chunk.iter_mut().zip(bytes.chunks_exact(8)) {
                *x = f64::from_le_bytes(b.try_into().expect("8 bytes"));
            }
        }
        Some(())
    };
    let projections: Option<Vec<LevelProjections>> = histories
        .projections
        .iter()
        .map(|l| LevelProjections::read(l.level, l.dofs, l.samples, &mut next))
        .collect();
    let Some(projections) = projections else {
        return stale(format!("{} ended early", bin.display()));
    };
    if hex(&digest.finalize()) != histories.checksum {
        return stale(format!(
            "its checksum does not match {} and {}: changed since written",
            json.display(),
            bin.display()
        ));
    }
    let non_finite = projections.iter().find_map(|p| {
        p.values()
            .position(|x| !x.is_finite() || x.abs() > LARGEST_VALUE)
            .map(|k| {
                format!(
                    "{}: value {k} of level {} is not finite or beyond {LARGEST_VALUE:e}",
                    bin.display(),
                    p.level
                )
            })
    });
    if let Some(why) = non_finite {
        return stale(why);
    }
    Ok(CacheLookup::Hit(Box::new(CachedReference {
        histories,
        projections,
    })))
}

/// The environment variable that names the reference cache the commands use when they are not
/// given `--cache` ([`user_cache`]).
pub const CACHE_VARIABLE: &str = "SIGNORINI_CACHE";

/// The reference cache of this user, which every command shares when it is not given
/// `--cache`: `$SIGNORINI_CACHE` when set (and not empty), else `signorini/references` under
/// the platform's cache directory (`dirs::cache_dir`: `$XDG_CACHE_HOME` or `~/.cache` on Linux,
/// `~/Library/Caches` on macOS); `None` when neither is known.
pub fn user_cache() -> Option<PathBuf> {
    std::env::var_os(CACHE_VARIABLE)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| dirs::cache_dir().map(|d| d.join("signorini").join("references")))
}

/// Where a study's reference is looked up, and whether it is kept there.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReferenceCache {
    /// Read the directory, and save a reference computed for want of a cache into it.
    ReadWrite(PathBuf),
    /// Read the directory; a reference computed for want of a cache is not saved.
    ReadOnly(PathBuf),
}

impl ReferenceCache {
    /// The directory.
    pub fn dir(&self) -> &Path {
        match self {
            ReferenceCache::ReadWrite(dir) | ReferenceCache::ReadOnly(dir) => dir,
        }
    }
}

/// The cached reference of `dir` of the same dimension as `key` whose key differs from it in
/// the fewest fields (its file name, those fields); `None` when there is none.
pub(super) fn closest_other(dir: &Path, key: &ReferenceKey) -> Option<(String, Vec<String>)> {
    let prefix = format!("reference-{}d-", key.lengths.len());
    std::fs::read_dir(dir)
        .ok()?
        .filter_map(Result::ok)
        .filter_map(|entry| {
            let name = entry.file_name().to_string_lossy().into_owned();
            if !(name.starts_with(&prefix) && name.ends_with(".json")) {
                return None;
            }
            let histories: ReferenceHistories =
                input::read_json(&entry.path(), REFERENCE_JSON).ok()?;
            Some((name, key.differences(&histories.key)))
        })
        .min_by_key(|(_, fields)| fields.len())
}

/// What a cache holds of a reference: its histories and its projections.
#[derive(Debug)]
pub struct CachedReference {
    /// The scalar histories, the key and the check.
    pub histories: ReferenceHistories,
    /// The projections on each fitted level, coarsest first.
    pub projections: Vec<LevelProjections>,
}

/// The outcome of looking for a cached reference.
#[derive(Debug)]
pub enum CacheLookup {
    /// Found, with an equal key.
    Hit(Box<CachedReference>),
    /// No cache file.
    Missing,
    /// A cache for other parameters (the differing fields).
    Stale(Vec<String>),
}
