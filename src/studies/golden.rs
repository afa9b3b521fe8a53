//! What `make golden` runs: the studies under the gate, each written to its golden file (the
//! file names belong to the studies: [`GOLDEN_TABLES`], [`GOLDEN_GRAVITY`], [`GOLDEN_EXTENDED`],
//! [`GOLDEN_ELASTIC_2D`]; the format to `crate::harness::study::golden`).

use std::path::Path;

use crate::harness::files::artifacts::write_json;
use crate::harness::study::golden::{read_golden, Golden, Tolerances};
use crate::harness::study::Case;
use crate::studies::elastic_study::gate::{
    elastic_gate_sensitivity, elastic_gate_study, GOLDEN_ELASTIC_2D,
};
use crate::studies::error::Error;
use crate::studies::extended::{
    extended_studies_with_sensitivity, read_extended_golden, ExtendedGolden, GOLDEN_EXTENDED,
};
use crate::studies::gravity::{gravity_sensitivity, gravity_study, GOLDEN_GRAVITY};
use crate::studies::tables::{tables_sensitivity, tables_study, GOLDEN_TABLES};

/// Runs the studies under the gate and writes their golden files under `root`, keeping the
/// tolerances (and their per-norm overrides) of the files they replace.
pub fn write_golden(root: &Path) -> Result<Vec<(String, Golden)>, Error> {
    let studies = [
        (
            GOLDEN_TABLES,
            tables_study(root)?,
            Some(tables_sensitivity(root, &Case::tables_matrix())?),
        ),
        {
            let study = gravity_study(root)?;
            let cases: Vec<Case> = study.cases.iter().map(|c| c.case).collect();
            let sensitivity = gravity_sensitivity(root, &cases)?;
            (GOLDEN_GRAVITY, study, Some(sensitivity))
        },
        (
            GOLDEN_ELASTIC_2D,
            elastic_gate_study(root)?.study,
            Some(elastic_gate_sensitivity(root, None)?),
        ),
    ];
    let mut written = Vec::new();
    let path = root.join(GOLDEN_EXTENDED);
    let previous = read_extended_golden(&path).ok();
    let extended =
        ExtendedGolden::from_studies(&extended_studies_with_sensitivity(root)?, previous.as_ref());
    write_json(&path, &extended)?;
    for t in extended.treatments {
        written.push((format!("{GOLDEN_EXTENDED} [{}]", t.contact), t.golden));
    }
    for (name, study, sensitivity) in studies {
        let path = root.join(name);
        let tolerances =
            read_golden(&path).map_or_else(|_| Tolerances::default(), |g| g.tolerances);
        let mut golden = Golden::from_study(&study, tolerances);
        if let Some(s) = &sensitivity {
            golden = golden.with_sensitivity(s);
        }
        write_json(&path, &golden)?;
        written.push((name.to_string(), golden));
    }
    Ok(written)
}
