//! The fine-mesh reference of a 2D/3D study (the note §3 has no exact solution: "(U, λ) can be
//! approximated by (U_h^n, λ^n) by taking Δt and Δx very small"), and its cache.
//!
//! A reference is one run on the finest nested mesh. It keeps, every `sample_every` fine steps,
//! the energy (eq. 6), the total normal contact force `Σ λ_i` and the contact-face centre node's
//! displacement and multiplier; for each fitted level, at each of that level's steps, the
//! reference's projections on the level ([`crate::harness::run::nested_comparison::projection`]),
//! which is all a coarse run's displacement errors need; and the distance to it of the reference
//! case one level coarser, run beside it in lockstep
//! ([`crate::harness::run::nested_comparison::check`]). Its trajectory is never stored: memory is
//! the run's own and the projections (about 100 MB for the 3D levels 10–80).
//!
//! The cache is two files under a directory: `<stem>.json` (the [`ReferenceKey`], the scalar
//! histories, the check) and `<stem>.bin` (the projections, little-endian `f64`, level after
//! level in [`LevelProjections::values`] order). The stem names the key
//! ([`ReferenceKey::stem`]), so references of different parameters live side by side and none
//! evicts another. A cache is used only when its key equals the key of the reference asked for,
//! field by field; otherwise it is recomputed. A [`ReferenceCache`] says whether the run may
//! write the directory.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, sync_channel};
use std::time::Instant;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::harness::files::artifacts::write_atomic;
use crate::harness::files::error::{Error, ParameterError};
use crate::harness::files::input::{self, InputError, JsonError, Limit};
use crate::harness::files::manifest::hex;
use crate::harness::problem::{Conventions, MassVariant, Scheme, Settings};
use crate::harness::run::distributed::{
    distributed_run, follow_run, lockstep_run, DecompositionError, Ranks, SlabObserver,
    SlabObservers,
};
use crate::harness::run::elastic::run_box;
use crate::harness::run::elastic::{box_mesh, BoxMesh, BoxProblem};
use crate::harness::run::nested_comparison::check::{
    CheckComparison, CheckGather, CheckSender, LockstepCheck,
};
use crate::harness::run::nested_comparison::norm_matrices::NormMatrices;
use crate::harness::run::nested_comparison::projection::{LevelProjections, ProjectionRecorder};
use crate::harness::run::{run, Observables, RunConfig, Timings};
use crate::harness::study::progress::StepProgress;

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
    /// bytes ([`Reference::save`]): a cache changed since it was written is stale.
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

/// A reference: the histories and the projections on the fitted levels, with its mesh.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The scalar histories, the key and the check.
    pub histories: ReferenceHistories,
    /// The projections on each fitted level, coarsest first.
    pub projections: Vec<LevelProjections>,
    /// The fine mesh.
    pub mesh: BoxMesh,
    /// Whether it was read from the cache.
    pub from_cache: bool,
    /// What the fine run cost, when it was computed now.
    pub cost: Option<FineRunCost>,
}

/// What a reference's fine run cost.
#[derive(Debug, Clone, Copy)]
pub struct FineRunCost {
    /// How its time was spent (rank 0's, for a distributed run).
    pub timings: Timings,
    /// Step systems solved.
    pub solves: usize,
    /// CG iterations over all of them.
    pub iterations: usize,
    /// The ranks the check run was shared by (1: in one process, [`lockstep_check`]).
    pub check_ranks: usize,
    /// `L`, the layers of the local contact operator's slab (rank 0's), when it has one.
    pub contact_layers: Option<usize>,
}

impl Reference {
    /// Runs the reference, projecting it on `key.levels` as it goes, with the check run one
    /// level coarser beside it, and keeps the scalar histories every `key.sample_every`-th step;
    /// with `ranks`, as rank 0 of a distributed run, whose steps the other ranks share
    /// ([`Reference::follow`]; the projections and the check are computed on every rank's slab,
    /// rank 0 keeping them, [`crate::harness::run::distributed`]).
    pub fn compute(
        problem: &BoxProblem,
        settings: &Settings,
        key: ReferenceKey,
        ranks: Option<&dyn Ranks>,
    ) -> Result<Self, Error> {
        let clock = Instant::now();
        let settings = match ranks {
            Some(_) => settings.distributed()?,
            None => *settings,
        };
        let config = fine_config(&key, settings)?;
        let every = key.sample_every.max(1);
        let mesh = box_mesh(problem, key.n_axis)?;
        let fine_norms = NormMatrices::of(&mesh, &problem.elasticity);
        let mesh_of = |n| box_mesh(problem, n).map_err(Error::from);
        let recorder = RefCell::new(ProjectionRecorder::new(
            (&key.levels, &mesh_of),
            (&mesh, &fine_norms),
            &problem.elasticity,
            ranks,
        )?);
        let check_config = RunConfig {
            nx: key.n_axis / 2,
            ..config.clone()
        };
        // The check run's steps per sample: it has half the reference's steps.
        let check_stride = (every / 2).max(1);
        let check_mesh = box_mesh(problem, check_config.nx)?;
        // Beside a distributed reference, every rank together: the check run distributed too,
        // stepped by the reference's steps, unless it cannot be cut into the ranks' slabs.
        let (lockstep_to, lockstep_from) = channel();
        let gather = ranks.map(|r| {
            let to = (r.rank() == 0).then_some(lockstep_to);
            RefCell::new(CheckGather::new(r, to, check_stride, &check_mesh))
        });
        let gather_observers: Vec<&RefCell<dyn SlabObserver>> = (gather.iter())
            .map(|g| g as &RefCell<dyn SlabObserver>)
            .collect();
        let lockstep = match (ranks, &gather) {
            (Some(r), Some(g)) => {
                lockstep_check(problem, &check_config, (r, &gather_observers, g))?
            }
            _ => None,
        };
        let (sender, receiver) = sync_channel(1);
        let receiver = if lockstep.is_some() {
            lockstep_from
        } else {
            receiver
        };
        let comparison = RefCell::new(match ranks {
            None => CheckComparison::new(receiver, &fine_norms, &check_mesh, &mesh, every)?,
            Some(ranks) => CheckComparison::distributed(
                ranks,
                Some(receiver),
                &fine_norms,
                (&check_mesh, &mesh),
                every,
            ),
        });
        let (run, distance, in_one_process) = std::thread::scope(|scope| {
            let check = lockstep.is_none().then(|| {
                scope.spawn(|| {
                    let mut send = CheckSender::new(sender, check_stride);
                    run(problem, &check_config, &mut [&mut send])
                })
            });
            let mut steps = StepProgress::new(
                &format!("reference on {} elements", key.n_axis),
                problem.horizon,
            );
            let slab_observers = fine_observers(&recorder, lockstep.as_ref(), &comparison);
            let run = match ranks {
                None => run_box(
                    problem,
                    (&config, None),
                    &mut [
                        &mut *recorder.borrow_mut(),
                        &mut *comparison.borrow_mut(),
                        &mut steps,
                    ],
                ),
                Some(ranks) => run_box(
                    problem,
                    (&config, Some(&*distributed_run(ranks, &slab_observers))),
                    &mut [&mut steps],
                ),
            };
            let distance = comparison.into_inner().finish();
            let in_one_process = check.map(|c| {
                c.join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            });
            (run, distance, in_one_process)
        });
        let run = run?.completed()?;
        let (check_dofs, check_steps, check_ranks) = match (in_one_process, lockstep) {
            (Some(check), _) => {
                let check = check?.completed()?;
                (check.dofs, check.steps, 1)
            }
            (None, Some(lockstep)) => (
                check_mesh.n_dofs(),
                lockstep.into_inner().finish()?,
                ranks.map_or(1, |r| r.size()),
            ),
            (None, None) => unreachable!("the check ran in one process or in lockstep"),
        };
        let cost = FineRunCost {
            timings: run.timings,
            solves: run.observed.step_solves.solves,
            iterations: run.observed.step_solves.iterations,
            check_ranks,
            contact_layers: run.observed.contact_slab.map(|t| t.layers),
        };
        let projections = recorder.into_inner().finish();
        let gap = problem.obstacle_gap.unwrap_or(0.0);
        let pick = |v: &[f64]| v.iter().step_by(every).copied().collect::<Vec<f64>>();
        let centre_displacement: Vec<f64> = run
            .observed
            .contact
            .centre_gap
            .iter()
            .map(|g| g - gap)
            .collect();
        let energy: Vec<f64> = run.observed.energy.iter().map(|&(_, e)| e).collect();
        let histories = ReferenceHistories {
            dofs: run.dofs,
            steps: run.steps,
            dt: run.dt,
            seconds: clock.elapsed().as_secs_f64(),
            time: run
                .observed
                .energy
                .iter()
                .step_by(every)
                .map(|&(t, _)| t)
                .collect(),
            energy: pick(&energy),
            total_force: pick(&run.observed.contact.total_force),
            centre_displacement: pick(&centre_displacement),
            centre_multiplier: pick(&run.observed.contact.centre_multiplier),
            projections: projections
                .iter()
                .map(|p| ProjectionLayout {
                    level: p.level,
                    dofs: p.dofs,
                    samples: p.samples(),
                })
                .collect(),
            check: CheckOutcome {
                level: check_config.nx,
                dofs: check_dofs,
                steps: check_steps,
                distance: distance
                    .into_iter()
                    .map(|(norm, d)| (norm.key().to_string(), d))
                    .collect(),
            },
            key,
            checksum: String::new(),
        };
        Ok(Self {
            mesh,
            histories,
            projections,
            from_cache: false,
            cost: Some(cost),
        })
    }

    /// Number of samples of the scalar histories.
    pub fn samples(&self) -> usize {
        self.histories.time.len()
    }

    /// The projections on the level of `n_axis` elements along the axis.
    pub fn projections_on(&self, n_axis: usize) -> Option<&LevelProjections> {
        self.projections.iter().find(|p| p.level == n_axis)
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
    pub fn save(&self, dir: &Path, stem: &str) -> Result<(), Error> {
        let (json, bin) = Self::cache_paths(dir, stem);
        let bytes: Vec<u8> = self
            .projections
            .iter()
            .flat_map(LevelProjections::values)
            .flat_map(f64::to_le_bytes)
            .collect();
        write_atomic(&bin, &bytes)?;
        let mut digest = self.histories.digest().map_err(Error::encode(&json))?;
        digest.update(&bytes);
        let histories = ReferenceHistories {
            checksum: hex(&digest.finalize()),
            ..self.histories.clone()
        };
        let text = serde_json::to_string(&histories).map_err(Error::encode(&json))?;
        write_atomic(&json, text.as_bytes())
    }

    /// Reads the cache if it exists and its key equals `key`: stale when the key differs, the
    /// `.bin` file has another size than its layout says, the checksum does not match or a
    /// value is not finite. A file that is not a regular one is an error.
    pub fn load(
        problem: &BoxProblem,
        dir: &Path,
        stem: &str,
        key: &ReferenceKey,
    ) -> Result<CacheLookup, Error> {
        let (json, bin) = Self::cache_paths(dir, stem);
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
        if let Some(why) = histories.non_finite() {
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
            p.values().position(|x| !x.is_finite()).map(|k| {
                format!(
                    "{}: value {k} of level {} is not finite",
                    bin.display(),
                    p.level
                )
            })
        });
        if let Some(why) = non_finite {
            return stale(why);
        }
        Ok(CacheLookup::Hit(Box::new(Self {
            mesh: box_mesh(problem, histories.key.n_axis)?,
            histories,
            projections,
            from_cache: true,
            cost: None,
        })))
    }

    /// The cached reference of `key` in `cache` when there is one, otherwise a new run, saved
    /// when `cache` may be written. `note` is told why a cache was not used: no file for the
    /// key (with the closest other reference of the same dimension and the fields it differs
    /// in), or a file whose content does not match. The run is solved with `settings`; settings
    /// with a round-off perturbation are refused: the key cannot tell it from the problem as
    /// stated. `afford` is asked before a run is started (a caller's budget check: its error
    /// is returned and nothing is run).
    ///
    /// With `ranks`, this is rank 0 of a distributed run: it tells the other ranks whether it
    /// computes the reference ([`Reference::follow`]) once the cache is looked up and the
    /// budget checked.
    pub fn obtain(
        problem: &BoxProblem,
        settings: &Settings,
        (cache, key): (&ReferenceCache, ReferenceKey),
        note: &mut dyn FnMut(String),
        afford: &dyn Fn() -> Result<(), Error>,
        ranks: Option<&dyn Ranks>,
    ) -> Result<Self, Error> {
        if settings.round_off.is_some() {
            return Err(ParameterError::new(
                "round_off",
                "given",
                "absent for a reference (its key and cache describe the problem as stated)",
            )
            .into());
        }
        let (dir, stem) = (cache.dir(), key.stem());
        match Self::load(problem, dir, &stem, &key)? {
            CacheLookup::Hit(reference) => {
                if let Some(ranks) = ranks {
                    ranks.sum(0.0);
                }
                return Ok(*reference);
            }
            CacheLookup::Missing => note(
                format!(
                    "no cached reference for these parameters in {}{}",
                    dir.display(),
                    closest_other(dir, &key)
                        .map(|(name, fields)| format!(
                            " (the closest, {name}, differs in {})",
                            fields.join("; ")
                        ))
                        .unwrap_or_default()
                ) + "; computing it",
            ),
            CacheLookup::Stale(why) => note(format!(
                "cached reference {stem} is stale ({}); computing it",
                why.join("; ")
            )),
        }
        afford()?;
        if let Some(ranks) = ranks {
            ranks.sum(1.0);
        }
        let reference = Self::compute(problem, settings, key, ranks)?;
        if let ReferenceCache::ReadWrite(dir) = cache {
            reference.save(dir, &stem)?;
        } else {
            note(format!(
                "the reference is not cached: the study writes nothing without --out or \
                 --cache DIR (it looked in {})",
                dir.display()
            ));
        }
        Ok(reference)
    }
}

impl Reference {
    /// A rank other than 0 of the distributed reference of `key` (rank 0 runs
    /// [`Reference::obtain`] with the same arguments): when rank 0 computes it, this rank's
    /// share of the fine run's steps ([`follow_run`]) and of the check run's, stepped by them
    /// ([`lockstep_check`]; unless the check cannot be cut into the ranks' slabs, when rank 0
    /// runs it in one process); nothing when rank 0 found it cached.
    pub fn follow(
        problem: &BoxProblem,
        settings: &Settings,
        key: &ReferenceKey,
        ranks: &dyn Ranks,
    ) -> Result<(), Error> {
        if ranks.sum(0.0) == 0.0 {
            return Ok(());
        }
        let config = fine_config(key, settings.distributed()?)?;
        let mesh = box_mesh(problem, key.n_axis)?;
        let fine_norms = NormMatrices::of(&mesh, &problem.elasticity);
        let mesh_of = |n| box_mesh(problem, n).map_err(Error::from);
        let recorder = RefCell::new(ProjectionRecorder::new(
            (&key.levels, &mesh_of),
            (&mesh, &fine_norms),
            &problem.elasticity,
            Some(ranks),
        )?);
        let check_config = RunConfig {
            nx: key.n_axis / 2,
            ..config.clone()
        };
        let check_mesh = box_mesh(problem, check_config.nx)?;
        let comparison = RefCell::new(CheckComparison::distributed(
            ranks,
            None,
            &fine_norms,
            (&check_mesh, &mesh),
            key.sample_every.max(1),
        ));
        let gather = RefCell::new(CheckGather::new(
            ranks,
            None,
            (key.sample_every / 2).max(1),
            &check_mesh,
        ));
        let gather_observers: [&RefCell<dyn SlabObserver>; 1] = [&gather];
        let lockstep = lockstep_check(problem, &check_config, (ranks, &gather_observers, &gather))?;
        let slab_observers = fine_observers(&recorder, lockstep.as_ref(), &comparison);
        follow_run(problem, &config, (ranks, &slab_observers))?;
        match lockstep {
            Some(lockstep) => lockstep
                .into_inner()
                .finish()
                .map(|_| ())
                .map_err(Error::from),
            None => Ok(()),
        }
    }
}

/// The reference run's configuration of `key`, solved with `settings`.
fn fine_config(key: &ReferenceKey, settings: Settings) -> Result<RunConfig, Error> {
    Ok(RunConfig {
        nx: key.n_axis,
        ratio: key.ratio,
        scheme: key.scheme.parse()?,
        mass: key.mass.parse()?,
        observables: Observables::default(),
        settings,
    })
}

/// A distributed reference's slab observers on every rank, in their order: the projections,
/// the check run's steps when it is stepped by the reference's (before the comparison that
/// reads their samples), and the comparison.
fn fine_observers<'o, 'a: 'o, 'b: 'o, 'c: 'o>(
    recorder: &'o RefCell<ProjectionRecorder<'a>>,
    lockstep: Option<&'o RefCell<LockstepCheck<'b>>>,
    comparison: &'o RefCell<CheckComparison<'c>>,
) -> Vec<&'o RefCell<dyn SlabObserver + 'o>> {
    let mut observers: Vec<&'o RefCell<dyn SlabObserver + 'o>> = vec![recorder];
    if let Some(lockstep) = lockstep {
        observers.push(lockstep);
    }
    observers.push(comparison);
    observers
}

/// Every rank's check run (`config`) beside a distributed reference on `ranks`, observed by
/// `observers` (its `gather`), stepped by the reference's steps ([`LockstepCheck`]); `None`
/// when its box cannot be cut into the ranks' slabs (its contact slab leaves no layer for some
/// rank: every rank learns it together, before any step), in which case rank 0 runs it in one
/// process beside the reference, as a reference in one process does.
fn lockstep_check<'r>(
    problem: &BoxProblem,
    config: &RunConfig,
    (ranks, observers, gather): (
        &'r dyn Ranks,
        &'r SlabObservers<'r>,
        &'r RefCell<CheckGather<'r>>,
    ),
) -> Result<Option<RefCell<LockstepCheck<'r>>>, Error> {
    match lockstep_run(problem, config, (ranks, observers)) {
        Ok(run) => Ok(Some(RefCell::new(LockstepCheck::new(run, gather)))),
        Err(Error::Distributed(DecompositionError::TooManyRanks { .. })) => Ok(None),
        Err(e) => Err(e),
    }
}

/// Where a study's reference is looked up, and whether it is kept there.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReferenceCache {
    /// Read the directory, and save a reference computed for want of a cache into it.
    ReadWrite(PathBuf),
    /// Read the directory; a reference computed for want of a cache is not saved (a study
    /// without `--out` writes nothing).
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
fn closest_other(dir: &Path, key: &ReferenceKey) -> Option<(String, Vec<String>)> {
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

/// The outcome of looking for a cached reference.
#[derive(Debug)]
pub enum CacheLookup {
    /// Found, with an equal key.
    Hit(Box<Reference>),
    /// No cache file.
    Missing,
    /// A cache for other parameters (the differing fields).
    Stale(Vec<String>),
}
