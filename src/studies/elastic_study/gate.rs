//! The gated 2D study (`make golden`, `tests/elastic_study.rs`): the 2D scene's levels and
//! cases against a coarser reference than `make report` uses, its golden file
//! [`GOLDEN_ELASTIC_2D`], and the round-off sensitivity the gate holds chaotic cases to.

use std::path::Path;

use super::{run_elastic_study, ElasticStudy};
use crate::harness::files::error::ParameterError;
use crate::harness::problem::LinearSolver;
use crate::harness::reference::fine_mesh::cache::ReferenceCache;
use crate::harness::reference::fine_mesh::ElasticStudyConfig;
use crate::harness::study::scene::Scene;
use crate::harness::study::sensitivity::Sensitivity;
use crate::harness::study::Case;
use crate::studies::error::Error;

/// The golden file of the gated 2D study, relative to the repository root.
pub const GOLDEN_ELASTIC_2D: &str = "golden/rates-2d.json";

/// The scene of the gated 2D study.
pub const ELASTIC_2D_SCENE: &str = "scenes/bar2d.json";

/// The reference level of the gated 2D study: the scene's levels and cases against a reference
/// on 320 elements along the axis (about 10 s in all), where `make report` uses the scene's
/// finer one.
pub const ELASTIC_GATE_REFERENCE_LEVEL: usize = 320;

/// The gated 2D study (the scene's cases, no ensemble), its reference computed afresh (in a
/// temporary directory, removed after).
pub fn elastic_gate_study(root: &Path) -> Result<ElasticStudy, Error> {
    elastic_gate(root, None, false)
}

/// The round-off sensitivity of `cases` (`None`: the scene's) on the gated 2D study (its levels
/// and reference) with the ensemble the scene declares: what `make golden` attaches to the 2D
/// golden file and what the gate holds the chaotic cases to.
pub fn elastic_gate_sensitivity(root: &Path, cases: Option<&[Case]>) -> Result<Sensitivity, Error> {
    elastic_gate(root, cases, true)?.sensitivity.ok_or_else(|| {
        ParameterError::new(
            "discretisation.sensitivity",
            "absent",
            "an ensemble {members, amplitude} (the 2D gate holds its study with one)",
        )
        .into()
    })
}

/// The gated 2D study of `cases` (`None`: the scene's), with the scene's ensemble when
/// `with_ensemble`, its reference computed afresh (in a temporary directory, removed after).
fn elastic_gate(
    root: &Path,
    cases: Option<&[Case]>,
    with_ensemble: bool,
) -> Result<ElasticStudy, Error> {
    let scene = Scene::load(&root.join(ELASTIC_2D_SCENE))?;
    let problem = scene.box_problem("a box scene: the 2D gate studies one")?;
    // The gate keeps the direct solver at every level, its reference too (21 120 unknowns, where
    // `auto` would take CG): its golden values are held at the round-off of one solver, and CG's
    // residual tolerance moves the errors by a few times the ensemble's spread (up to 6.1e-9
    // relative, on the CN/redistributed energy error at level 80), over their 1e-9 floor.
    let mut config = ElasticStudyConfig::from_scene(&scene, Some(ELASTIC_GATE_REFERENCE_LEVEL))?;
    config.settings.linear_solver = LinearSolver::Direct;
    if let Some(cases) = cases {
        config.cases = cases.to_vec();
    }
    if !with_ensemble {
        config.sensitivity = None;
    }
    let cache = std::env::temp_dir().join(format!(
        "signorini-gate-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    let result = run_elastic_study(
        &problem,
        &config,
        &ReferenceCache::ReadWrite(cache.clone()),
        &mut |_| {},
    );
    let _ = std::fs::remove_dir_all(&cache);
    Ok(result?.0)
}
