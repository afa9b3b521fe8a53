//! One run of GetFEM's demo read into typed values: a gzipped JSON file of
//! `tests/data/getfem/` (its README lists the fields and the demo's conventions), and the
//! directory listing with the file-name convention.
//!
//! The reader keeps what the comparisons use: the configuration of `params`, the demo's own
//! seven norms, the arrays (`TT`, `store_*`) and `final_state`; the provenance fields (`timing`,
//! `demo_stdout_tail`, …) are skipped. Non-finite values come two ways: the runner wrote those
//! of the arrays as `null` (`inf` and `NaN` alike), read as `NaN`; Python's `json` wrote those of
//! `params` (the norms of a run that blew up) as the bare words `Infinity`, `-Infinity` and
//! `NaN`, which are not JSON and are read as the values they name.
//!
//! Memory is bounded: a file larger than [`MAX_COMPRESSED_BYTES`], or one that inflates to more
//! than [`MAX_JSON_BYTES`] of JSON, is rejected before it is parsed (the largest run kept,
//! NX = 40, is 0.1 MB compressed and 0.3 MB of JSON; NX = 1280 would be about 10 MB of JSON).

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt;

use std::io::Read;
use std::path::{Path, PathBuf};

use flate2::read::GzDecoder;
use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer};
use serde_json::{Map, Value};

use super::norms::{DemoErrorNorms, DemoSeries};
use crate::engine::contact::ContactTreatment;
use crate::engine::error::ParameterError;
use crate::engine::fem::MassVariant;
use crate::engine::schemes::Scheme;
use crate::harness::files::input::{self, InputError, Limit};
use crate::harness::getfem::error::DemoRunError;

/// The largest run file accepted, in bytes (compressed).
pub const MAX_COMPRESSED_BYTES: u64 = 8 << 20;

/// The largest JSON text a run file may inflate to, in bytes.
pub const MAX_JSON_BYTES: u64 = 32 << 20;

/// A GetFEM demo run file, as [`input`] reads it.
const DEMO_RUN_FILE: Limit = Limit {
    what: "GetFEM demo run",
    max_bytes: MAX_COMPRESSED_BYTES,
};

/// The demo's `version`: how contact is treated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DemoVersion {
    /// 0: Signorini contact with a multiplier, implicit Newmark.
    Signorini,
    /// 1: Paoli–Schatzman (restitution `e_PS`).
    PaoliSchatzman,
    /// 2: penalty, stiffness `γ0_P / h`.
    Penalty,
    /// 3: Nitsche, `γ = γ0_N / h`, variant `θ_N`.
    Nitsche,
    /// 4: Taylor–Flanagan, explicit (β = 0).
    TaylorFlanagan,
}

impl DemoVersion {
    const ALL: [DemoVersion; 5] = [
        DemoVersion::Signorini,
        DemoVersion::PaoliSchatzman,
        DemoVersion::Penalty,
        DemoVersion::Nitsche,
        DemoVersion::TaylorFlanagan,
    ];

    /// The demo's number for it (0–4).
    pub fn code(self) -> u64 {
        self as u64
    }

    fn from_code(code: u64) -> Option<Self> {
        Self::ALL.into_iter().find(|v| v.code() == code)
    }
}

/// The demo's `mass_matrix_type`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DemoMass {
    /// 0: the consistent P1 mass.
    Consistent,
    /// 1: the demo's "redistributed" mass (`M[1,1] += M[0,0] + M[1,0]`, row and column 0
    /// zeroed).
    Redistributed,
    /// 2: the demo's "singular dynamic" mass (`M[1,1] = 7h/12`, row and column 0 zeroed).
    SingularDynamic,
}

impl DemoMass {
    const ALL: [DemoMass; 3] = [
        DemoMass::Consistent,
        DemoMass::Redistributed,
        DemoMass::SingularDynamic,
    ];

    /// The demo's number for it (0–2).
    pub fn code(self) -> u64 {
        self as u64
    }

    fn from_code(code: u64) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.code() == code)
    }
}

/// The configuration of a run (its `params`, the demo's names in brackets).
#[derive(Debug, Clone, PartialEq)]
pub struct DemoConfig {
    /// `version`.
    pub version: DemoVersion,
    /// Newmark `beta`.
    pub beta: f64,
    /// Newmark `gamma`.
    pub gamma: f64,
    /// Paoli–Schatzman restitution `e_PS`.
    pub e_ps: f64,
    /// Penalty parameter `gamma0_P` (stiffness `γ0_P / h`).
    pub gamma0_p: f64,
    /// Nitsche parameter `gamma0_N` (`γ = γ0_N / h`).
    pub gamma0_n: f64,
    /// Nitsche variant `theta_N`.
    pub theta_n: f64,
    /// `mass_matrix_type`.
    pub mass: DemoMass,
    /// `lump_mass_matrix = 1`: row sums on the diagonal.
    pub lumped: bool,
    /// Number of elements `NX`.
    pub nx: usize,
    /// Time step `dt`.
    pub dt: f64,
    /// Horizon `T`.
    pub horizon: f64,
}

impl DemoConfig {
    /// The scheme the harness runs for it: Paoli–Schatzman with the demo's `β` and `e_PS` for
    /// version 1, Newmark with its `β` and `γ` otherwise (Taylor–Flanagan is Newmark `β = 0`).
    pub fn scheme(&self) -> Scheme {
        match self.version {
            DemoVersion::PaoliSchatzman => Scheme::PaoliSchatzman {
                beta: self.beta,
                restitution: self.e_ps,
            },
            _ => Scheme::Newmark {
                beta: self.beta,
                gamma: self.gamma,
            },
        }
    }

    /// The harness's mass variant of the demo's mass: consistent (lumped with
    /// `lump_mass_matrix`), or the demo's own types 1 and 2.
    pub fn mass_variant(&self) -> MassVariant {
        match (self.mass, self.lumped) {
            (DemoMass::Consistent, false) => MassVariant::Standard,
            (DemoMass::Consistent, true) => MassVariant::Lumped,
            (DemoMass::Redistributed, _) => MassVariant::GetfemRedistributed,
            (DemoMass::SingularDynamic, _) => MassVariant::GetfemSingular,
        }
    }

    /// The harness's contact treatment of the demo's version, its parameters checked: the
    /// penalty's `γ0_P` and Nitsche's `γ0_N`, `θ_N` (with `E = 1` the harness's `γ₀ E / h` is
    /// the demo's `γ0 / h`); the multiplier otherwise.
    pub fn contact(&self) -> Result<ContactTreatment, ParameterError> {
        match self.version {
            DemoVersion::Penalty => ContactTreatment::Penalty {
                gamma0: self.gamma0_p,
            },
            DemoVersion::Nitsche => ContactTreatment::Nitsche {
                theta: self.theta_n,
                gamma0: self.gamma0_n,
            },
            _ => ContactTreatment::Multiplier,
        }
        .validate()
    }
}

/// The fields at `t = T` (`final_state`), one value per node `x_i = i/NX`, the clamped node
/// `x = 1` included.
#[derive(Debug, Clone, PartialEq)]
pub struct DemoFinalState {
    /// `x_dofs`: the node positions.
    pub x: Vec<f64>,
    /// `U`.
    pub u: Vec<f64>,
    /// `V`.
    pub v: Vec<f64>,
    /// `Uex`: the exact displacement at the nodes.
    pub u_ex: Vec<f64>,
    /// `Vex`: the exact velocity at the nodes.
    pub v_ex: Vec<f64>,
}

/// One run of the demo.
#[derive(Debug, Clone, PartialEq)]
pub struct DemoRun {
    /// Its configuration.
    pub config: DemoConfig,
    /// The demo's own final norms (`params.LinfL2u`, …), `NaN` where it printed a
    /// non-finite value.
    pub norms: DemoErrorNorms,
    /// The arrays, one value per time point `TT` (`t = 0` included).
    pub series: DemoSeries,
    /// `store_E`: the demo's energy `(VᵀMV + UᵀKU)/2` with its mass matrix (plus the contact
    /// term of penalty and Nitsche).
    pub energy: Vec<f64>,
    /// The fields at `t = T`.
    pub final_state: DemoFinalState,
}

/// What a run file's name says (`tests/data/getfem/README.md`):
/// `getfem_v{version}_b{beta}_g{gamma}[_e{e}|_gP{γ0}|_gN{γ0}_tN{θ}][_lump]_m{mass}_nx{NX}[_k{K}].json.gz`.
#[derive(Debug, Clone, PartialEq)]
pub struct DemoRunName {
    /// `v`.
    pub version: DemoVersion,
    /// `b`: Newmark β.
    pub beta: f64,
    /// `g`: Newmark γ.
    pub gamma: f64,
    /// `e`: the Paoli–Schatzman restitution, when the name gives it.
    pub e_ps: Option<f64>,
    /// `gP`: the penalty parameter, when the name gives it.
    pub gamma0_p: Option<f64>,
    /// `gN`: the Nitsche parameter, when the name gives it.
    pub gamma0_n: Option<f64>,
    /// `tN`: the Nitsche variant, when the name gives it.
    pub theta_n: Option<f64>,
    /// `_lump`.
    pub lumped: bool,
    /// `m`.
    pub mass: DemoMass,
    /// `nx`.
    pub nx: usize,
    /// `Δx/Δt`: 10, or `K` of a `_k{K}` suffix (`_k2`: `Δt = 1/(2 NX)`).
    pub ratio: usize,
}

/// A run file of a directory with what its name says.
#[derive(Debug, Clone, PartialEq)]
pub struct DemoRunFile {
    /// The file.
    pub path: PathBuf,
    /// Its name, parsed.
    pub name: DemoRunName,
}

const PREFIX: &str = "getfem_";
const SUFFIX: &str = ".json.gz";

impl DemoRunName {
    /// Parses the name of the file `path` (its directory is ignored). A name that does not
    /// follow the convention is a [`DemoRunError::Name`] saying which part does not fit.
    pub fn parse(path: &Path) -> Result<Self, DemoRunError> {
        Self::parse_name(path).map_err(|problem| DemoRunError::Name {
            path: path.to_path_buf(),
            problem,
        })
    }

    fn parse_name(path: &Path) -> Result<Self, String> {
        let file = path
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or("no UTF-8 file name")?;
        let stem = file
            .strip_prefix(PREFIX)
            .and_then(|s| s.strip_suffix(SUFFIX))
            .ok_or(format!("it must start with {PREFIX} and end with {SUFFIX}"))?;
        let mut parts = NameParts {
            parts: stem.split('_').collect(),
            next: 0,
        };
        let version = parts.integer("v")?;
        let version = DemoVersion::from_code(version)
            .ok_or(format!("version {version} is not one of 0 to 4"))?;
        let beta = parts.number("b")?;
        let gamma = parts.number("g")?;
        let (mut e_ps, mut gamma0_p, mut gamma0_n, mut theta_n) = (None, None, None, None);
        if parts.peek("gP") {
            gamma0_p = Some(parts.number("gP")?);
        } else if parts.peek("gN") {
            gamma0_n = Some(parts.number("gN")?);
            theta_n = Some(parts.number("tN")?);
        } else if parts.peek("e") {
            e_ps = Some(parts.number("e")?);
        }
        let lumped = parts.flag("lump");
        let mass = parts.integer("m")?;
        let mass =
            DemoMass::from_code(mass).ok_or(format!("mass type {mass} is not one of 0 to 2"))?;
        let nx = parts.integer("nx")?;
        let ratio = if parts.peek("k") {
            parts.integer("k")?
        } else {
            10
        };
        if nx == 0 || ratio == 0 {
            return Err(format!("nx{nx}, k{ratio}: both must be at least 1"));
        }
        if let Some(extra) = parts.parts.get(parts.next) {
            return Err(format!("`{extra}` after the last part"));
        }
        Ok(Self {
            version,
            beta,
            gamma,
            e_ps,
            gamma0_p,
            gamma0_n,
            theta_n,
            lumped,
            mass,
            nx: nx as usize,
            ratio: ratio as usize,
        })
    }

    /// The time step the name implies, `Δt = 1/(ratio NX)`.
    pub fn dt(&self) -> f64 {
        1.0 / (self.ratio * self.nx) as f64
    }

    /// Checks that `config` (read from the file `path`) is what the name says: every parameter
    /// the name gives, and `dt` to 1e-12 relative.
    fn check(&self, path: &Path, config: &DemoConfig) -> Result<(), DemoRunError> {
        let mismatch = |field: &str, found: String, named: String| DemoRunError::Field {
            path: path.to_path_buf(),
            field: format!("params.{field}"),
            found,
            expected: format!("{named}, as the file name says"),
        };
        let numbers = [
            ("beta", config.beta, Some(self.beta)),
            ("gamma", config.gamma, Some(self.gamma)),
            ("e_PS", config.e_ps, self.e_ps),
            ("gamma0_P", config.gamma0_p, self.gamma0_p),
            ("gamma0_N", config.gamma0_n, self.gamma0_n),
            ("theta_N", config.theta_n, self.theta_n),
        ];
        for (field, found, named) in numbers {
            if let Some(named) = named.filter(|&n| n != found) {
                return Err(mismatch(field, found.to_string(), named.to_string()));
            }
        }
        let codes = [
            ("version", config.version.code(), self.version.code()),
            ("mass_matrix_type", config.mass.code(), self.mass.code()),
            ("lump_mass_matrix", config.lumped as u64, self.lumped as u64),
            ("NX", config.nx as u64, self.nx as u64),
        ];
        for (field, found, named) in codes {
            if found != named {
                return Err(mismatch(field, found.to_string(), named.to_string()));
            }
        }
        if (config.dt - self.dt()).abs() > 1e-12 * self.dt() {
            return Err(mismatch(
                "dt",
                config.dt.to_string(),
                format!("1/({} NX) = {}", self.ratio, self.dt()),
            ));
        }
        Ok(())
    }
}

/// The `_`-separated parts of a run file name, read in order.
struct NameParts<'a> {
    parts: Vec<&'a str>,
    next: usize,
}

impl NameParts<'_> {
    /// Whether the next part is `word`, taken if it is.
    fn flag(&mut self, word: &str) -> bool {
        let found = self.parts.get(self.next) == Some(&word);
        self.next += found as usize;
        found
    }

    /// Whether the next part starts with `tag`.
    fn peek(&self, tag: &str) -> bool {
        self.parts
            .get(self.next)
            .is_some_and(|p| p.starts_with(tag))
    }

    /// The value of the next part, which must be `tag` followed by it.
    fn value(&mut self, tag: &str) -> Result<&str, String> {
        let part = self.parts.get(self.next).copied().unwrap_or("");
        self.next += 1;
        part.strip_prefix(tag)
            .ok_or(format!("`{part}` where `{tag}…` is expected"))
    }

    fn number(&mut self, tag: &str) -> Result<f64, String> {
        let text = self.value(tag)?;
        text.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or(format!("`{tag}{text}`: `{text}` is not a number"))
    }

    fn integer(&mut self, tag: &str) -> Result<u64, String> {
        let text = self.value(tag)?;
        text.parse::<u64>()
            .map_err(|_| format!("`{tag}{text}`: `{text}` is not a non-negative integer"))
    }
}

/// The run files of `dir`: the files named `getfem_*.json.gz`, sorted by file name, each with
/// its parsed name. Other files (the README) are skipped; a `getfem_*.json.gz` whose name does
/// not follow the convention is an error.
pub fn list_runs(dir: &Path) -> Result<Vec<DemoRunFile>, DemoRunError> {
    let io = |source| DemoRunError::Io {
        path: dir.to_path_buf(),
        source,
    };
    let mut runs = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let is_run = path
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| n.starts_with(PREFIX) && n.ends_with(SUFFIX));
        if is_run {
            let name = DemoRunName::parse(&path)?;
            runs.push(DemoRunFile { path, name });
        }
    }
    runs.sort_by(|a, b| a.path.file_name().cmp(&b.path.file_name()));
    Ok(runs)
}

/// Reads the run file `path`: its name ([`DemoRunName::parse`]), then the gzipped JSON within
/// the size limits, then every field the reader keeps, checked: the configuration in range
/// (`version` 0–4, `mass_matrix_type` 0–2, `lump_mass_matrix` 0–1, `NX ≥ 1`, `dt`, `T` > 0,
/// `u_degree = 1`) and as the file name says, the arrays all as long as `TT`, the final fields
/// all of `NX + 1` values. Each failure names the file and the field.
pub fn read_run(path: &Path) -> Result<DemoRun, DemoRunError> {
    let name = DemoRunName::parse(path)?;
    let raw: RawRun = {
        let text = inflate(path)?;
        serde_json::from_slice(&quote_python_literals(&text)).map_err(|source| {
            DemoRunError::Json {
                path: path.to_path_buf(),
                source,
            }
        })?
    };
    raw.into_run(path, &name)
}

/// The JSON text of the gzipped file `path`, within the size limits.
fn inflate(path: &Path) -> Result<Vec<u8>, DemoRunError> {
    let io = |source| DemoRunError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = input::open(path, DEMO_RUN_FILE).map_err(|e| match e {
        InputError::TooLarge { .. } => DemoRunError::TooLarge {
            path: path.to_path_buf(),
            what: "compressed file",
            limit: MAX_COMPRESSED_BYTES,
        },
        InputError::Io { source, .. } => io(source),
        other => DemoRunError::Input(other),
    })?;
    gunzip_json(file).map_err(|e| match e {
        Gunzip::Corrupt(source) => DemoRunError::Gzip {
            path: path.to_path_buf(),
            source,
        },
        Gunzip::TooLarge => DemoRunError::TooLarge {
            path: path.to_path_buf(),
            what: "decompressed JSON",
            limit: MAX_JSON_BYTES,
        },
    })
}

/// Why a gzipped JSON file was not inflated.
pub(super) enum Gunzip {
    /// Not gzip, or cut short.
    Corrupt(std::io::Error),
    /// More than [`MAX_JSON_BYTES`] inflated.
    TooLarge,
}

/// The inflated text of the gzip stream `file`: refused once it passes [`MAX_JSON_BYTES`], so
/// that a small file cannot fill the memory.
pub(super) fn gunzip_json(file: impl Read) -> Result<Vec<u8>, Gunzip> {
    let mut text = Vec::new();
    GzDecoder::new(file)
        .take(MAX_JSON_BYTES + 1)
        .read_to_end(&mut text)
        .map_err(Gunzip::Corrupt)?;
    if text.len() as u64 > MAX_JSON_BYTES {
        return Err(Gunzip::TooLarge);
    }
    Ok(text)
}

/// The words Python's `json` writes for non-finite floats, and their values.
const PYTHON_LITERALS: [(&[u8], f64); 3] = [
    (b"-Infinity", f64::NEG_INFINITY),
    (b"Infinity", f64::INFINITY),
    (b"NaN", f64::NAN),
];

/// `text` with every [`PYTHON_LITERALS`] word outside a string put in quotes, which makes it
/// JSON: a string the readers of numbers take for the value it names ([`number_or_literal`]).
/// Outside strings, valid JSON has no other bare word holding these letters.
fn quote_python_literals(text: &[u8]) -> Cow<'_, [u8]> {
    let mut out: Option<Vec<u8>> = None;
    let (mut in_string, mut escaped) = (false, false);
    let mut i = 0;
    while i < text.len() {
        let byte = text[i];
        if in_string {
            match byte {
                _ if escaped => escaped = false,
                b'\\' => escaped = true,
                b'"' => in_string = false,
                _ => {}
            }
        } else if byte == b'"' {
            in_string = true;
        } else if let Some((word, _)) = PYTHON_LITERALS
            .iter()
            .find(|(word, _)| text[i..].starts_with(word))
        {
            let out = out.get_or_insert_with(|| text[..i].to_vec());
            out.push(b'"');
            out.extend_from_slice(word);
            out.push(b'"');
            i += word.len();
            continue;
        }
        if let Some(out) = out.as_mut() {
            out.push(byte);
        }
        i += 1;
    }
    out.map_or(Cow::Borrowed(text), Cow::Owned)
}

/// A number; `null` as `NaN`; a quoted Python literal (`"Infinity"`, `"-Infinity"`, `"NaN"`)
/// as its value; `None` for anything else.
fn number_or_literal(value: &Value) -> Option<f64> {
    match value {
        Value::Null => Some(f64::NAN),
        Value::Number(n) => n.as_f64(),
        Value::String(s) => PYTHON_LITERALS
            .iter()
            .find(|(word, _)| *word == s.as_bytes())
            .map(|&(_, v)| v),
        _ => None,
    }
}

/// The sections of a run file the reader keeps, before their checks.
#[derive(Deserialize)]
struct RawRun {
    params: Map<String, Value>,
    #[serde(deserialize_with = "arrays_section")]
    arrays: BTreeMap<String, Vec<f64>>,
    #[serde(deserialize_with = "final_state_section")]
    final_state: BTreeMap<String, Vec<f64>>,
}

fn arrays_section<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<BTreeMap<String, Vec<f64>>, D::Error> {
    deserializer.deserialize_map(Section { name: "arrays" })
}

fn final_state_section<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<BTreeMap<String, Vec<f64>>, D::Error> {
    deserializer.deserialize_map(Section {
        name: "final_state",
    })
}

/// A JSON object of named arrays of numbers and nulls (`null` read as `NaN`), each error
/// naming its array.
struct Section {
    name: &'static str,
}

impl<'de> Visitor<'de> for Section {
    type Value = BTreeMap<String, Vec<f64>>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "`{}`: an object of arrays", self.name)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut out = BTreeMap::new();
        while let Some(key) = map.next_key::<String>()? {
            let field = format!("{}.{key}", self.name);
            let values = map.next_value_seed(Series { field: &field })?;
            out.insert(key, values);
        }
        Ok(out)
    }
}

/// One array of numbers and nulls, named `field` in its errors.
struct Series<'a> {
    field: &'a str,
}

impl<'de> DeserializeSeed<'de> for Series<'_> {
    type Value = Vec<f64>;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Vec<f64>, D::Error> {
        deserializer.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for Series<'_> {
    type Value = Vec<f64>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "`{}`: an array of numbers and nulls", self.field)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<f64>, A::Error> {
        let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 16));
        while let Some(value) = seq.next_element::<Value>()? {
            match number_or_literal(&value) {
                Some(v) => out.push(v),
                None => {
                    return Err(de::Error::custom(format_args!(
                        "`{}[{}]` is {value}, not a number, null, Infinity or NaN",
                        self.field,
                        out.len()
                    )))
                }
            }
        }
        Ok(out)
    }
}

impl RawRun {
    /// The checked run of the file `path` named `name`.
    fn into_run(self, path: &Path, name: &DemoRunName) -> Result<DemoRun, DemoRunError> {
        let params = Params {
            path,
            map: &self.params,
        };
        let code = |key: &str, max: u64| params.integer(key, max);
        let version = DemoVersion::from_code(code("version", 4)?).expect("checked to be 0–4");
        let mass = DemoMass::from_code(code("mass_matrix_type", 2)?).expect("checked to be 0–2");
        let lumped = code("lump_mass_matrix", 1)? == 1;
        let degree = code("u_degree", u64::MAX)?;
        if degree != 1 {
            return Err(params.error("u_degree", degree.to_string(), "1 (P1 elements)"));
        }
        let nx = code("NX", u64::MAX)?;
        if nx == 0 {
            return Err(params.error("NX", "0".into(), "an integer >= 1"));
        }
        let config = DemoConfig {
            version,
            beta: params.number("beta")?,
            gamma: params.number("gamma")?,
            e_ps: params.number("e_PS")?,
            gamma0_p: params.number("gamma0_P")?,
            gamma0_n: params.number("gamma0_N")?,
            theta_n: params.number("theta_N")?,
            mass,
            lumped,
            nx: nx as usize,
            dt: params.positive("dt")?,
            horizon: params.positive("T")?,
        };
        name.check(path, &config)?;
        let norm = |key: &str| params.norm(key);
        let norms = DemoErrorNorms {
            linf_l2_u: norm("LinfL2u")?,
            linf_h1_u: norm("LinfH1u")?,
            linf_l2_v: norm("LinfL2v")?,
            l2_l2_u: norm("L2L2u")?,
            l2_h1_u: norm("L2H1u")?,
            l2_l2_v: norm("L2L2v")?,
            l2_sn: norm("L2sn")?,
        };
        let mut arrays = Arrays::new(path, "arrays", self.arrays);
        let time = arrays.take("TT", None)?;
        if time.is_empty() {
            return Err(arrays.error("TT", "empty".into(), "at least one time point"));
        }
        let steps = (config.horizon / config.dt).round();
        if steps + 1.0 != time.len() as f64 {
            return Err(params.error(
                "T",
                format!(
                    "{} with dt = {}: {steps} steps, but arrays.TT has {} time points",
                    config.horizon,
                    config.dt,
                    time.len()
                ),
                "T / dt + 1 time points in arrays.TT (the demo stores every step)",
            ));
        }
        let n = Some(time.len());
        let series = DemoSeries {
            time,
            u0: arrays.take("store_u0", n)?,
            u0_ex: arrays.take("store_u0_ex", n)?,
            v0: arrays.take("store_v0", n)?,
            v0_ex: arrays.take("store_v0_ex", n)?,
            s0: arrays.take("store_s0", n)?,
            s0_ex: arrays.take("store_s0_ex", n)?,
            u_l2: arrays.take("store_UL2", n)?,
            u_l2_ex: arrays.take("store_UL2_ex", n)?,
            u_h1: arrays.take("store_UH1", n)?,
            u_h1_ex: arrays.take("store_UH1_ex", n)?,
            v_l2: arrays.take("store_VL2", n)?,
            v_l2_ex: arrays.take("store_VL2_ex", n)?,
        };
        let energy = arrays.take("store_E", n)?;
        let mut fields = Arrays::new(path, "final_state", self.final_state);
        let nodes = Some(config.nx + 1);
        let final_state = DemoFinalState {
            x: fields.take("x_dofs", nodes)?,
            u: fields.take("U", nodes)?,
            v: fields.take("V", nodes)?,
            u_ex: fields.take("Uex", nodes)?,
            v_ex: fields.take("Vex", nodes)?,
        };
        Ok(DemoRun {
            config,
            norms,
            series,
            energy,
            final_state,
        })
    }
}

/// The `params` object of the file `path`, read field by field.
struct Params<'a> {
    path: &'a Path,
    map: &'a Map<String, Value>,
}

impl Params<'_> {
    fn error(&self, key: &str, found: String, expected: &str) -> DemoRunError {
        DemoRunError::Field {
            path: self.path.to_path_buf(),
            field: format!("params.{key}"),
            found,
            expected: expected.to_string(),
        }
    }

    fn get(&self, key: &str, expected: &str) -> Result<&Value, DemoRunError> {
        self.map
            .get(key)
            .ok_or_else(|| self.error(key, "missing".into(), expected))
    }

    /// An integer in `0..=max`.
    fn integer(&self, key: &str, max: u64) -> Result<u64, DemoRunError> {
        let expected = if max == u64::MAX {
            "a non-negative integer".to_string()
        } else {
            format!("an integer from 0 to {max}")
        };
        let value = self.get(key, &expected)?;
        value
            .as_u64()
            .filter(|&v| v <= max)
            .ok_or_else(|| self.error(key, value.to_string(), &expected))
    }

    /// A finite number.
    fn number(&self, key: &str) -> Result<f64, DemoRunError> {
        const EXPECTED: &str = "a finite number";
        let value = self.get(key, EXPECTED)?;
        value
            .as_f64()
            .filter(|v| v.is_finite())
            .ok_or_else(|| self.error(key, value.to_string(), EXPECTED))
    }

    /// A finite number > 0.
    fn positive(&self, key: &str) -> Result<f64, DemoRunError> {
        const EXPECTED: &str = "a finite number > 0";
        let value = self.get(key, EXPECTED)?;
        value
            .as_f64()
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| self.error(key, value.to_string(), EXPECTED))
    }

    /// A number, `Infinity`, `-Infinity`, `NaN`, or `null` (read as `NaN`).
    fn norm(&self, key: &str) -> Result<f64, DemoRunError> {
        const EXPECTED: &str = "a number, null, Infinity or NaN";
        let value = self.get(key, EXPECTED)?;
        number_or_literal(value).ok_or_else(|| self.error(key, value.to_string(), EXPECTED))
    }
}

/// A section of named arrays of the file `path`, taken out one by one.
struct Arrays<'a> {
    path: &'a Path,
    section: &'static str,
    arrays: BTreeMap<String, Vec<f64>>,
}

impl<'a> Arrays<'a> {
    fn new(path: &'a Path, section: &'static str, arrays: BTreeMap<String, Vec<f64>>) -> Self {
        Self {
            path,
            section,
            arrays,
        }
    }

    fn error(&self, key: &str, found: String, expected: &str) -> DemoRunError {
        DemoRunError::Field {
            path: self.path.to_path_buf(),
            field: format!("{}.{key}", self.section),
            found,
            expected: expected.to_string(),
        }
    }

    /// The array `key`, of `len` values when given.
    fn take(&mut self, key: &str, len: Option<usize>) -> Result<Vec<f64>, DemoRunError> {
        let values = self
            .arrays
            .remove(key)
            .ok_or_else(|| self.error(key, "missing".into(), "an array of numbers and nulls"))?;
        match len {
            Some(len) if values.len() != len => Err(self.error(
                key,
                format!("{} values long", values.len()),
                &format!("{len} values, one per {}", self.unit()),
            )),
            _ => Ok(values),
        }
    }

    fn unit(&self) -> &'static str {
        if self.section == "arrays" {
            "time point of TT"
        } else {
            "node (NX + 1)"
        }
    }
}
