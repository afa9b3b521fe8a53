//! GetFEM's own runs of the 2D and 3D bars (formats `signorini-getfem2d-anchor/1` and
//! `signorini-getfem3d-anchor/1`, in `tests/data/getfem2d/` and `getfem3d/`, whose READMEs give
//! the fields) rewritten in the box form of the external-run format ([`BoxFile`]), so that
//! `signorini verify` reads them as it reads any other code's runs (`signorini getfem-box`).
//!
//! Where each quantity of a run goes:
//! * per step `t_n`: the multipliers `λ_i ≤ 0` of the contact nodes → `multipliers`, reordered
//!   from the run's list (`contact_nodes_x1`, `contact_nodes_x`) to the box form's node order
//!   ([`NODE_ORDER`]); GetFEM's energy `½ VᵀM V + ½ UᵀS U` with the run's own mass → `energy`,
//!   declared `total-at-sample`;
//! * the displacement at the scene's `fields_at` steps and at `T` → `displacement` at those
//!   steps only, and the velocity at `T` → `velocity` at the last step.
//!
//! A run stores its fields at five steps, not at every step, so it is written as the JSON box
//! form (which allows that) rather than as a ParaView collection (which holds one snapshot per
//! step): the verification then gives the force norm at every step and the displacement errors
//! at the stored steps.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use super::demo_run::{gunzip_json, Gunzip};
use super::{MAX_COMPRESSED_BYTES, MAX_JSON_BYTES};
use crate::harness::external::box_run::{
    BoxFile, BoxFileMesh, BoxFileSample, EnergyDefinition, BOX_FORMAT, NODE_ORDER,
};
use crate::harness::external::format::Code;
use crate::harness::external::ExternalError;
use crate::harness::files::input::{self, Limit};
use crate::harness::problem::{MassVariant, Scheme};

/// The formats read, with the scene each run solves.
pub const ANCHOR_FORMATS: [(&str, &str); 2] = [
    ("signorini-getfem2d-anchor/1", "bar2d"),
    ("signorini-getfem3d-anchor/1", "bar3d"),
];

/// An anchor file, as read.
const ANCHOR_FILE: Limit = Limit {
    what: "GetFEM run file",
    max_bytes: MAX_COMPRESSED_BYTES,
};

/// How far a contact node's coordinate may be from its grid position, relative to the box's
/// largest length.
const COORDINATE_TOLERANCE: f64 = 1e-9;

/// One GetFEM run in the box form, with the file name it is written under.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvertedRun {
    /// `getfem-<d>d-<scheme>-<mass>-level<level>.json`.
    pub file_name: String,
    /// The run.
    pub run: BoxFile,
}

/// Reads the gzipped anchor run `path` and writes it in the box form.
pub fn convert_anchor(path: &Path) -> Result<ConvertedRun, ExternalError> {
    let text = inflate(path)?;
    let anchor: AnchorFile = serde_json::from_slice(&text).map_err(|e| ExternalError::Json {
        path: path.to_path_buf(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    anchor.into_box(path)
}

/// The JSON text of the gzipped file `path`, within [`MAX_COMPRESSED_BYTES`] compressed and
/// [`MAX_JSON_BYTES`] inflated.
fn inflate(path: &Path) -> Result<Vec<u8>, ExternalError> {
    let file = input::open(path, ANCHOR_FILE)?;
    gunzip_json(file).map_err(|e| match e {
        Gunzip::Corrupt(e) => {
            ExternalError::invalid(path, "file", None, e, "a gzipped JSON file (.json.gz)")
        }
        Gunzip::TooLarge => ExternalError::invalid(
            path,
            "file",
            None,
            format!("more than {MAX_JSON_BYTES} bytes of JSON"),
            format!("at most {MAX_JSON_BYTES} bytes inflated"),
        ),
    })
}

#[derive(Debug, Deserialize)]
struct AnchorFile {
    format: String,
    generator: Generator,
    params: Params,
    #[serde(default)]
    contact_nodes_x1: Option<Vec<f64>>,
    #[serde(default)]
    contact_nodes_x: Option<Vec<Vec<f64>>>,
    history: History,
    fields: Vec<StoredField>,
    #[serde(rename = "final")]
    last: FinalState,
}

#[derive(Debug, Deserialize)]
struct Generator {
    versions: BTreeMap<String, String>,
}

#[derive(Debug, Deserialize)]
struct Params {
    lengths: Vec<f64>,
    elements: Vec<usize>,
    level: usize,
    steps: usize,
    scheme: String,
    mass: String,
}

#[derive(Debug, Deserialize)]
struct History {
    time: Vec<f64>,
    multipliers: Vec<Vec<f64>>,
    energy: Vec<f64>,
}

#[derive(Debug, Deserialize)]
struct StoredField {
    step: usize,
    displacement: Vec<Vec<f64>>,
}

#[derive(Debug, Deserialize)]
struct FinalState {
    displacement: Vec<Vec<f64>>,
    velocity: Vec<Vec<f64>>,
}

impl AnchorFile {
    fn into_box(self, path: &Path) -> Result<ConvertedRun, ExternalError> {
        let invalid = |field: &str, value: String, allowed: String| {
            ExternalError::invalid(path, field, None, value, allowed)
        };
        let names: Vec<&str> = ANCHOR_FORMATS.iter().map(|(f, _)| *f).collect();
        let Some(&(_, scene)) = ANCHOR_FORMATS.iter().find(|(f, _)| *f == self.format) else {
            return Err(invalid(
                "format",
                format!("{:?}", self.format),
                names.join(", "),
            ));
        };
        let p = &self.params;
        let d = p.lengths.len();
        if !(2..=3).contains(&d) || p.elements.len() != d {
            return Err(invalid(
                "params.elements",
                format!("{:?} on lengths {:?}", p.elements, p.lengths),
                "one count per length of a 2D or 3D box".into(),
            ));
        }
        p.scheme
            .parse::<Scheme>()
            .map_err(|e| invalid("params.scheme", format!("{:?}", p.scheme), e.to_string()))?;
        let mass = p
            .mass
            .parse::<MassVariant>()
            .map_err(|e| invalid("params.mass", format!("{:?}", p.mass), e.to_string()))?;
        let version = self
            .generator
            .versions
            .iter()
            .find(|(k, _)| k.to_ascii_lowercase().contains("getfem"))
            .map(|(_, v)| v.clone())
            .ok_or_else(|| {
                invalid(
                    "generator.versions",
                    format!("{:?}", self.generator.versions.keys().collect::<Vec<_>>()),
                    "an entry naming GetFEM's version".into(),
                )
            })?;
        let h = &self.history;
        let samples = p.steps + 1;
        for (field, len) in [
            ("history.time", h.time.len()),
            ("history.multipliers", h.multipliers.len()),
            ("history.energy", h.energy.len()),
        ] {
            if len != samples {
                return Err(invalid(
                    field,
                    format!("{len} entries"),
                    format!("one per step t_0 … t_N: {samples}"),
                ));
            }
        }
        let order = self.contact_order(path)?;
        let mut displacement: BTreeMap<usize, Vec<Vec<f64>>> = BTreeMap::new();
        for field in self.fields {
            if field.step > p.steps {
                return Err(invalid(
                    "fields.step",
                    field.step.to_string(),
                    format!("a step of the run: 0 … {}", p.steps),
                ));
            }
            displacement.insert(field.step, field.displacement);
        }
        displacement.insert(p.steps, self.last.displacement);
        let mut velocity = Some(self.last.velocity);
        let mut rows = Vec::with_capacity(samples);
        for (n, ((&time, multipliers), &energy)) in
            h.time.iter().zip(&h.multipliers).zip(&h.energy).enumerate()
        {
            if multipliers.len() != order.len() {
                return Err(ExternalError::invalid(
                    path,
                    "history.multipliers",
                    Some(format!("step {n}")),
                    format!("{} values", multipliers.len()),
                    format!("one per contact node: {}", order.len()),
                ));
            }
            let mut in_order = vec![0.0; order.len()];
            for (k, &node) in order.iter().enumerate() {
                in_order[node] = multipliers[k];
            }
            rows.push(BoxFileSample {
                time,
                displacement: displacement.remove(&n),
                velocity: if n == p.steps { velocity.take() } else { None },
                multipliers: Some(in_order),
                total_force: None,
                energy: Some(energy),
            });
        }
        let file_name = format!("getfem-{d}d-{}-{}-level{}.json", p.scheme, p.mass, p.level);
        let run = BoxFile {
            format: BOX_FORMAT.to_string(),
            scene: scene.to_string(),
            code: Code {
                name: "GetFEM".to_string(),
                version,
            },
            label: format!("GetFEM {}, {}", p.scheme, p.mass),
            scheme: Some(p.scheme.clone()),
            mass: Some(mass),
            contact: Some(
                "GetFEM's nodal contact brick with a rigid obstacle (Alart–Curnier, exact \
                 complementarity)"
                    .to_string(),
            ),
            mesh: BoxFileMesh {
                lengths: p.lengths.clone(),
                elements: p.elements.clone(),
                node_order: NODE_ORDER.to_string(),
            },
            energy_definition: Some(EnergyDefinition::TotalAtSample),
            samples: rows,
        };
        Ok(ConvertedRun { file_name, run })
    }

    /// Per contact node of the run's list, its position in the box form's order: the face
    /// `x_d = 0`'s nodes `i_1 + (n_1 + 1) i_2`, found from the node's coordinates.
    fn contact_order(&self, path: &Path) -> Result<Vec<usize>, ExternalError> {
        let p = &self.params;
        let d = p.lengths.len();
        let coordinates: Vec<Vec<f64>> = match (&self.contact_nodes_x1, &self.contact_nodes_x) {
            (Some(x1), None) if d == 2 => x1.iter().map(|&x| vec![x]).collect(),
            (None, Some(x)) if d == 3 => x.clone(),
            _ => return Err(ExternalError::invalid(
                path,
                "contact_nodes_x1, contact_nodes_x",
                None,
                "missing, or the other dimension's",
                "contact_nodes_x1 (x1 per node) in 2D, contact_nodes_x ([x1, x2] per node) in 3D",
            )),
        };
        let face: usize = p.elements[..d - 1].iter().map(|n| n + 1).product();
        let scale = p.lengths.iter().fold(0.0f64, |a, &b| a.max(b));
        let mut seen = vec![false; face];
        let mut order = Vec::with_capacity(coordinates.len());
        for (k, x) in coordinates.iter().enumerate() {
            let mut node = 0;
            let mut stride = 1;
            let mut on_grid = x.len() == d - 1;
            for (c, &xc) in x.iter().enumerate().take(d - 1) {
                let h = p.lengths[c] / p.elements[c] as f64;
                let i = (xc / h).round();
                on_grid &= i >= 0.0
                    && i <= p.elements[c] as f64
                    && (xc - i * h).abs() <= COORDINATE_TOLERANCE * scale;
                node += i.max(0.0) as usize * stride;
                stride *= p.elements[c] + 1;
            }
            if !on_grid || node >= face || seen[node] {
                return Err(ExternalError::invalid(
                    path,
                    "contact nodes",
                    Some(format!("node {k}")),
                    format!("{x:?}"),
                    format!(
                        "the nodes of the face x{d} = 0 of the grid {:?} on {:?}, each once",
                        p.elements, p.lengths
                    ),
                ));
            }
            seen[node] = true;
            order.push(node);
        }
        if order.len() != face {
            return Err(ExternalError::invalid(
                path,
                "contact nodes",
                None,
                format!("{} nodes", order.len()),
                format!("every node of the face x{d} = 0: {face}"),
            ));
        }
        Ok(order)
    }
}
