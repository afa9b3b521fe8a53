//! The CSV form of an external run: `# key: value` metadata lines, a header row of named
//! columns (`time`, `u0…uNX`, `v0…vNX`, `lambda`, `lambda_time`, `contact_displacement`,
//! `energy`, `energy_time`, in any order), then one row of numbers per sample. Read line by
//! line ([`input::Lines`], each line at most [`MAX_LINE_BYTES`]), so a file never needs more
//! memory than its numbers and one line; the header is checked in time linear in its columns.
//!
//! Version 2 ([`Version::Two`]) adds the metadata `scheme`, `mass`, `contact` and
//! `energy_definition`
//! ([`OPTIONAL_METADATA_KEYS`]) and lets a `lambda` cell, or all the `u` (or `v`) cells of a
//! row, be empty or `null`: not computed at that sample.

use std::collections::{BTreeMap, HashSet};
use std::path::Path;

use super::error::ExternalError;
use super::format::{
    parse_energy_definition, parse_mass, parse_scheme, Code, ExternalRun, SampleOrigin,
    SampledField, Version, MAX_VALUES, RUN_FILE,
};
use crate::harness::files::input::{self, InputError};

/// The longest line read, in bytes (64 MiB: a row of a million nodes' displacement and
/// velocity at 32 characters a number).
pub const MAX_LINE_BYTES: usize = 64 * 1024 * 1024;

/// The metadata keys, all required.
pub const METADATA_KEYS: [&str; 6] = [
    "format",
    "scene",
    "code.name",
    "code.version",
    "label",
    "mesh.nodes",
];

/// The metadata keys a version 2 file may add, each at most once.
pub const OPTIONAL_METADATA_KEYS: [&str; 4] = ["scheme", "mass", "contact", "energy_definition"];

/// The cell that stands for "not computed" in version 2, besides an empty one.
const NULL: &str = "null";

/// The columns with one value per sample besides the fields (`time` is required).
pub const SCALAR_COLUMNS: [&str; 6] = [
    "time",
    "lambda",
    "lambda_time",
    "contact_displacement",
    "energy",
    "energy_time",
];

/// Counts the null cell in column `c` of a field's row: `(first null column, nulls)`.
fn null_cell(nulls: &mut (Option<usize>, usize), c: usize) {
    nulls.0.get_or_insert(c);
    nulls.1 += 1;
}

/// How many cells beyond the header's a row's error message counts.
const MAX_REPORTED_CELLS: usize = 1000;

/// What a header column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Column {
    /// One of [`SCALAR_COLUMNS`], by index.
    Scalar(usize),
    /// `u<i>`: the displacement at node `i`.
    Displacement(usize),
    /// `v<i>`: the velocity at node `i`.
    Velocity(usize),
}

impl Column {
    fn parse(name: &str) -> Option<Self> {
        if let Some(k) = SCALAR_COLUMNS.iter().position(|&c| c == name) {
            return Some(Column::Scalar(k));
        }
        let node = |rest: &str| rest.parse::<usize>().ok().filter(|i| rest == i.to_string());
        match name.split_at_checked(1)? {
            ("u", rest) => node(rest).map(Column::Displacement),
            ("v", rest) => node(rest).map(Column::Velocity),
            _ => None,
        }
    }
}

/// Reads the CSV run file `path` (at most [`super::format::MAX_FILE_BYTES`]).
pub fn read(path: &Path) -> Result<ExternalRun, ExternalError> {
    let lines = input::Lines::open(path, RUN_FILE, MAX_LINE_BYTES)?;
    Reader::new(path).read(lines)
}

/// The state of one file's reading.
struct Reader<'a> {
    path: &'a Path,
    metadata: BTreeMap<&'static str, String>,
}

impl<'a> Reader<'a> {
    fn new(path: &'a Path) -> Self {
        Self {
            path,
            metadata: BTreeMap::new(),
        }
    }

    fn invalid(
        &self,
        field: impl Into<String>,
        at: String,
        value: impl std::fmt::Display,
        allowed: impl Into<String>,
    ) -> ExternalError {
        ExternalError::invalid(self.path, field, Some(at), value, allowed)
    }

    fn read(
        mut self,
        mut lines: impl Iterator<Item = Result<(usize, String), InputError>>,
    ) -> Result<ExternalRun, ExternalError> {
        let (header_line, header) = loop {
            let Some(line) = lines.next() else {
                return Err(ExternalError::invalid(
                    self.path,
                    "header",
                    None,
                    "missing",
                    "a header row of column names after the `# key: value` lines",
                ));
            };
            let (number, text) = line?;
            if text.trim().is_empty() {
                continue;
            }
            match text.strip_prefix('#') {
                Some(meta) => self.metadata_line(number, meta)?,
                None => break (number, text),
            }
        };
        let mut meta = |key: &'static str| {
            self.metadata.remove(key).ok_or_else(|| {
                ExternalError::invalid(
                    self.path,
                    key,
                    None,
                    "missing",
                    format!("a `# {key}: …` line before the header"),
                )
            })
        };
        let format = meta("format")?;
        let scene = meta("scene")?;
        let code = Code {
            name: meta("code.name")?,
            version: meta("code.version")?,
        };
        let label = meta("label")?;
        let nodes_text = meta("mesh.nodes")?;
        let version = Version::parse(self.path, &format)?;
        let scheme = self
            .metadata
            .remove("scheme")
            .map(|s| parse_scheme(self.path, &s))
            .transpose()?;
        let mass = self
            .metadata
            .remove("mass")
            .map(|m| parse_mass(self.path, &m))
            .transpose()?;
        let contact = self.metadata.remove("contact");
        let energy_definition = self
            .metadata
            .remove("energy_definition")
            .map(|d| parse_energy_definition(self.path, &d))
            .transpose()?;
        let nodes = self.nodes(&nodes_text)?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let columns = self.header(header_line, &names, nodes.len())?;
        let n = nodes.len();
        let has = |c: fn(usize) -> Column| columns.contains(&c(0));
        let (has_u, has_v) = (has(Column::Displacement), has(Column::Velocity));
        let mut time = Vec::new();
        let mut fields = [has_u, has_v].map(|has| has.then(SampledField::default));
        let mut rows = [vec![0.0; n], vec![0.0; n]];
        let mut lambda = columns.contains(&Column::Scalar(1)).then(Vec::new);
        let mut scalars: [Option<Vec<f64>>; 4] =
            std::array::from_fn(|k| columns.contains(&Column::Scalar(k + 2)).then(Vec::new));
        let mut first_line = None;
        let mut blank = None;
        for line in lines {
            let (number, text) = line?;
            if text.trim().is_empty() {
                blank.get_or_insert(number);
                continue;
            }
            if let Some(empty) = blank {
                return Err(self.invalid(
                    "row",
                    format!("line {empty}"),
                    "an empty line",
                    "one row per sample, with no empty line between rows",
                ));
            }
            first_line.get_or_insert(number);
            if (time.len() + 1).saturating_mul(columns.len()) > MAX_VALUES {
                return Err(self.invalid(
                    "rows",
                    format!("line {number}"),
                    format!("{} rows of {} values", time.len() + 1, columns.len()),
                    format!("at most {MAX_VALUES} values in one file"),
                ));
            }
            let row = time.len();
            // Per field, the first of its cells that is null in this row and how many are.
            let mut nulls: [(Option<usize>, usize); 2] = [(None, 0); 2];
            let mut cells = text.split(',');
            for (c, &column) in columns.iter().enumerate() {
                let Some(cell) = cells.next() else {
                    return Err(self.wrong_width(number, c, columns.len()));
                };
                let null = version == Version::Two && matches!(cell.trim(), "" | NULL);
                let parse = || self.number(names[c], number, c, cell);
                match column {
                    Column::Scalar(0) => time.push(parse()?),
                    Column::Scalar(1) => {
                        let x = if null { None } else { Some(parse()?) };
                        if let Some(values) = lambda.as_mut() {
                            values.push(x);
                        }
                    }
                    Column::Scalar(k) => {
                        let x = parse()?;
                        if let Some(values) = scalars[k - 2].as_mut() {
                            values.push(x);
                        }
                    }
                    Column::Displacement(i) | Column::Velocity(i) => {
                        let f = usize::from(matches!(column, Column::Velocity(_)));
                        match null {
                            true => null_cell(&mut nulls[f], c),
                            false => rows[f][i] = parse()?,
                        }
                    }
                }
            }
            if cells.next().is_some() {
                let more = columns.len() + 1 + cells.take(MAX_REPORTED_CELLS).count();
                return Err(self.wrong_width(number, more, columns.len()));
            }
            for ((field, values), (first_null, count)) in fields.iter_mut().zip(&rows).zip(nulls) {
                let Some(field) = field else { continue };
                match first_null {
                    None => field.begin_row(row).extend_from_slice(values),
                    Some(_) if count == n => {}
                    Some(c) => {
                        return Err(self.invalid(
                            names[c],
                            format!("line {number}, column {}", c + 1),
                            "empty or null",
                            "a number, or every cell of the field in this row empty or null \
                             (no field at this sample)",
                        ))
                    }
                }
            }
        }
        let samples = time.len();
        let [displacement, velocity] = fields.map(|field| {
            field.map(|mut f| {
                f.finish(samples);
                f
            })
        });
        let [lambda_time, contact_displacement, energy, energy_time] = scalars;
        Ok(ExternalRun {
            path: self.path.to_path_buf(),
            origin: SampleOrigin::Csv {
                first_line: first_line.unwrap_or(header_line + 1),
            },
            version,
            scene,
            code,
            label,
            scheme,
            mass,
            contact,
            energy_definition,
            nodes,
            time,
            displacement,
            velocity,
            lambda,
            lambda_time,
            contact_displacement,
            energy,
            energy_time,
        })
    }

    /// A row of `found` values where the header has `columns` (`found` beyond
    /// [`MAX_REPORTED_CELLS`] extra cells is not counted further).
    fn wrong_width(&self, number: usize, found: usize, columns: usize) -> ExternalError {
        let found = if found > columns + MAX_REPORTED_CELLS {
            format!("more than {} values", columns + MAX_REPORTED_CELLS)
        } else {
            format!("{found} values")
        };
        self.invalid(
            "row",
            format!("line {number}"),
            found,
            format!("{columns} values, one per header column"),
        )
    }

    /// Takes in the metadata line `# key: value` (the text after `#`) at line `number`.
    fn metadata_line(&mut self, number: usize, meta: &str) -> Result<(), ExternalError> {
        let allowed = format!(
            "`# key: value` lines with a key among {} (and, in signorini-external/2, {}), each \
             once",
            METADATA_KEYS.join(", "),
            OPTIONAL_METADATA_KEYS.join(", ")
        );
        let Some((key, value)) = meta.split_once(':') else {
            return Err(self.invalid("metadata", format!("line {number}"), meta.trim(), allowed));
        };
        let key = key.trim();
        let mut known = METADATA_KEYS.iter().chain(&OPTIONAL_METADATA_KEYS);
        match known.find(|&&k| k == key) {
            Some(&k) if !self.metadata.contains_key(k) => {
                self.metadata.insert(k, value.trim().to_string());
                Ok(())
            }
            _ => Err(self.invalid("metadata", format!("line {number}"), key, allowed)),
        }
    }

    /// The positions of `# mesh.nodes: x0, x1, …`.
    fn nodes(&self, text: &str) -> Result<Vec<f64>, ExternalError> {
        if text.split(',').nth(MAX_VALUES).is_some() {
            return Err(self.invalid(
                "mesh.nodes",
                "its line".to_string(),
                format!("more than {MAX_VALUES} nodes"),
                format!("at most {MAX_VALUES} values in one file"),
            ));
        }
        text.split(',')
            .enumerate()
            .map(|(i, x)| {
                let x = x.trim();
                match x.parse::<f64>() {
                    Ok(v) if v.is_finite() => Ok(v),
                    _ => Err(self.invalid(
                        "mesh.nodes",
                        format!("node {i}"),
                        format!("{x:?}"),
                        "finite numbers separated by commas",
                    )),
                }
            })
            .collect()
    }

    /// The header's columns: known names, each once, `time` among them, and the nodal
    /// columns of a field all present (`n` nodes) or all absent.
    fn header(&self, line: usize, names: &[&str], n: usize) -> Result<Vec<Column>, ExternalError> {
        let allowed = format!(
            "{}, u0…u{last}, v0…v{last} (one per mesh node), each once",
            SCALAR_COLUMNS.join(", "),
            last = n - 1
        );
        let mut columns = Vec::with_capacity(names.len());
        let mut seen = HashSet::with_capacity(names.len());
        for (c, &name) in names.iter().enumerate() {
            let at = format!("line {line}, column {}", c + 1);
            let column = Column::parse(name)
                .filter(|col| match col {
                    Column::Displacement(i) | Column::Velocity(i) => *i < n,
                    Column::Scalar(_) => true,
                })
                .ok_or_else(|| {
                    self.invalid("columns", at.clone(), format!("{name:?}"), &allowed)
                })?;
            if !seen.insert(column) {
                return Err(self.invalid("columns", at, format!("{name:?} again"), &allowed));
            }
            columns.push(column);
        }
        if !seen.contains(&Column::Scalar(0)) {
            return Err(self.invalid("time", format!("line {line}"), "missing", "a `time` column"));
        }
        for (prefix, field) in [
            ("u", Column::Displacement as fn(usize) -> Column),
            ("v", Column::Velocity),
        ] {
            let count = (0..n).filter(|&i| seen.contains(&field(i))).count();
            if count > 0 && count < n {
                let missing = (0..n).find(|&i| !seen.contains(&field(i))).unwrap_or(0);
                return Err(self.invalid(
                    format!("{prefix}{missing}"),
                    format!("line {line}"),
                    "missing",
                    format!(
                        "every {prefix}0…{prefix}{} (one per mesh node) or none",
                        n - 1
                    ),
                ));
            }
        }
        Ok(columns)
    }

    /// The number `cell` in column `c` (0-based, named `name`) of line `number`, finite.
    fn number(
        &self,
        name: &str,
        number: usize,
        c: usize,
        cell: &str,
    ) -> Result<f64, ExternalError> {
        let at = format!("line {number}, column {}", c + 1);
        match cell.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(_) => Err(self.invalid(
                name,
                at,
                cell.trim(),
                "a finite number: a run that went non-finite has no error norm",
            )),
            Err(_) => Err(self.invalid(name, at, format!("{:?}", cell.trim()), "a number")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::fem::MassVariant;
    use crate::harness::external::format::EnergyDefinition;

    /// `text` written as `name` into a scratch directory, then read.
    fn read_text(name: &str, text: &str) -> Result<ExternalRun, ExternalError> {
        let dir = std::env::temp_dir().join(format!("signorini-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        read(&path)
    }

    /// A version 2 file: λ null at t = 0, the fields at the last two samples.
    const V2: &str = "\
# format: signorini-external/2
# scene: bar1d-dirichlet
# code.name: test
# code.version: 0
# label: v2
# scheme: paoli-schatzman(beta=0.25,e=0.5)
# mass: lumped
# contact: multiplier, semi-smooth Newton
# energy_definition: staggered
# mesh.nodes: 0, 0.5, 1
time,u0,u1,u2,lambda,energy
0,,,,null,0.125
1.5,0,-0.25,0,-0.5,0.125
3,0.5,0.25,0,,0.125
";

    fn field_and_place(result: Result<ExternalRun, ExternalError>) -> (String, Option<String>) {
        match result {
            Err(ExternalError::Invalid { field, at, .. }) => (field, at),
            other => panic!("expected an invalid field, got {other:?}"),
        }
    }

    #[test]
    fn version_2_reads_null_cells_and_its_declarations() {
        let run = read_text("v2.csv", V2).unwrap();
        assert_eq!(run.version, Version::Two);
        assert_eq!(
            run.scheme.map(|s| s.name()).as_deref(),
            Some("paoli-schatzman-e0.5")
        );
        assert_eq!(run.mass, Some(MassVariant::Lumped));
        assert_eq!(
            run.contact.as_deref(),
            Some("multiplier, semi-smooth Newton")
        );
        assert_eq!(run.energy_definition, Some(EnergyDefinition::Staggered));
        assert_eq!(run.lambda, Some(vec![None, Some(-0.5), None]));
        assert_eq!(run.displacement.as_ref().unwrap().sampled(), 2);
        assert_eq!(run.row(&run.displacement, 0), None);
        assert_eq!(run.row(&run.displacement, 1), Some(&[0.0, -0.25, 0.0][..]));
        assert_eq!(run.energy, Some(vec![0.125; 3]));
    }

    #[test]
    fn null_cells_are_refused_in_version_1_and_in_part_of_a_row() {
        let part = V2.replace("\n1.5,0,-0.25,", "\n1.5,0,,");
        let expected = ("u1".to_string(), Some("line 13, column 3".to_string()));
        assert_eq!(field_and_place(read_text("part.csv", &part)), expected);
        let v1 = V2
            .replace("external/2", "external/1")
            .replace("# mass: lumped\n", "")
            .replace("# energy_definition: staggered\n", "")
            .replace("# scheme: paoli-schatzman(beta=0.25,e=0.5)\n", "")
            .replace("# contact: multiplier, semi-smooth Newton\n", "");
        let expected = ("u0".to_string(), Some("line 8, column 2".to_string()));
        assert_eq!(field_and_place(read_text("v1.csv", &v1)), expected);
        let energy_null = V2.replace(",0.125\n3,", ",null\n3,");
        let expected = ("energy".to_string(), Some("line 13, column 6".to_string()));
        assert_eq!(
            field_and_place(read_text("energy.csv", &energy_null)),
            expected
        );
        let bad_mass = V2.replace("# mass: lumped", "# mass: heavy");
        let message = read_text("mass.csv", &bad_mass).unwrap_err().to_string();
        assert!(
            message.contains("invalid mass = \"heavy\"") && message.contains("singular-dynamic"),
            "{message}"
        );
    }
}
