//! The CSV form of an external run: `# key: value` metadata lines, a header row of named
//! columns (`time`, `u0…uNX`, `v0…vNX`, `lambda`, `lambda_time`, `contact_displacement`,
//! `energy`, `energy_time`, in any order), then one row of numbers per sample. Read line by
//! line ([`input::Lines`], each line at most [`MAX_LINE_BYTES`]), so a file never needs more
//! memory than its numbers and one line; the header is checked in time linear in its columns.

use std::collections::{BTreeMap, HashSet};
use std::path::Path;

use super::error::ExternalError;
use super::format::{Code, ExternalRun, SampleOrigin, FORMAT, MAX_VALUES, RUN_FILE};
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

/// The columns with one value per sample besides the fields (`time` is required).
pub const SCALAR_COLUMNS: [&str; 6] = [
    "time",
    "lambda",
    "lambda_time",
    "contact_displacement",
    "energy",
    "energy_time",
];

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
        if format != FORMAT {
            return Err(ExternalError::invalid(
                self.path,
                "format",
                None,
                format!("{format:?}"),
                format!("{FORMAT:?}"),
            ));
        }
        let nodes = self.nodes(&nodes_text)?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let columns = self.header(header_line, &names, nodes.len())?;
        let n = nodes.len();
        let has = |c: fn(usize) -> Column| columns.contains(&c(0));
        let (has_u, has_v) = (has(Column::Displacement), has(Column::Velocity));
        let mut time = Vec::new();
        let mut u = Vec::new();
        let mut v = Vec::new();
        let mut scalars: [Option<Vec<f64>>; 5] =
            std::array::from_fn(|k| columns.contains(&Column::Scalar(k + 1)).then(Vec::new));
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
            if has_u {
                u.resize(u.len() + n, 0.0);
            }
            if has_v {
                v.resize(v.len() + n, 0.0);
            }
            let row = time.len();
            let mut cells = text.split(',');
            for (c, &column) in columns.iter().enumerate() {
                let Some(cell) = cells.next() else {
                    return Err(self.wrong_width(number, c, columns.len()));
                };
                let x = self.number(names[c], number, c, cell)?;
                match column {
                    Column::Scalar(0) => time.push(x),
                    Column::Scalar(k) => {
                        if let Some(values) = scalars[k - 1].as_mut() {
                            values.push(x);
                        }
                    }
                    Column::Displacement(i) => u[row * n + i] = x,
                    Column::Velocity(i) => v[row * n + i] = x,
                }
            }
            if cells.next().is_some() {
                let more = columns.len() + 1 + cells.take(MAX_REPORTED_CELLS).count();
                return Err(self.wrong_width(number, more, columns.len()));
            }
        }
        let [lambda, lambda_time, contact_displacement, energy, energy_time] = scalars;
        Ok(ExternalRun {
            path: self.path.to_path_buf(),
            origin: SampleOrigin::Csv {
                first_line: first_line.unwrap_or(header_line + 1),
            },
            scene,
            code,
            label,
            nodes,
            time,
            displacement: has_u.then_some(u),
            velocity: has_v.then_some(v),
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
            "`# key: value` lines with a key among {}, each once",
            METADATA_KEYS.join(", ")
        );
        let Some((key, value)) = meta.split_once(':') else {
            return Err(self.invalid("metadata", format!("line {number}"), meta.trim(), allowed));
        };
        let key = key.trim();
        match METADATA_KEYS.iter().find(|&&k| k == key) {
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
