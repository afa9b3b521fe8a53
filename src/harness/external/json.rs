//! The JSON form of an external run, read as a stream: every number goes from the file
//! straight into the flat arrays of the [`ExternalRun`] (no sample, row or text is held
//! whole), each checked finite as it comes and counted against [`MAX_VALUES`], every sample
//! checked to carry the fields sample 0 carries, each row as long as sample 0's (and, at the
//! end, as the mesh). Unknown and duplicate fields are refused.
//!
//! Memory: the arrays, at most [`MAX_VALUES`] numbers of 8 bytes, grow by doubling, so reading
//! takes at most three times their final size, 384 MiB, whatever the file holds.

use std::fmt;
use std::path::Path;

use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;

use super::error::ExternalError;
use super::format::{Code, ExternalRun, SampleOrigin, FORMAT, MAX_VALUES, RUN_FILE};
use crate::harness::files::input;

/// The top-level fields.
#[derive(Deserialize)]
#[serde(field_identifier, rename_all = "snake_case")]
enum Field {
    Format,
    Scene,
    Code,
    Label,
    Mesh,
    Samples,
}

/// The fields of `mesh`.
#[derive(Deserialize)]
#[serde(field_identifier, rename_all = "snake_case")]
enum MeshField {
    Nodes,
}

/// The fields of a sample, in the order of [`SAMPLE_FIELDS`].
#[derive(Deserialize, Clone, Copy)]
#[serde(field_identifier, rename_all = "snake_case")]
enum SampleField {
    Time,
    Displacement,
    Velocity,
    Lambda,
    LambdaTime,
    ContactDisplacement,
    Energy,
    EnergyTime,
}

/// The per-sample scalar fields besides `time`, in [`ExternalRun`]'s order.
const SCALARS: [&str; 5] = [
    "lambda",
    "lambda_time",
    "contact_displacement",
    "energy",
    "energy_time",
];

/// The nodal fields.
const FIELDS: [&str; 2] = ["displacement", "velocity"];

/// The names of [`SampleField`]'s fields, in its order.
const SAMPLE_FIELDS: [&str; 8] = [
    "time",
    "displacement",
    "velocity",
    "lambda",
    "lambda_time",
    "contact_displacement",
    "energy",
    "energy_time",
];

/// Reads the JSON run file `path` (at most [`super::format::MAX_FILE_BYTES`]).
pub fn read(path: &Path) -> Result<ExternalRun, ExternalError> {
    let mut arrays = Arrays::new(path);
    let parsed = input::read_json_seed(path, RUN_FILE, RunSeed(&mut arrays));
    if let Some(problem) = arrays.problem.take() {
        return Err(problem);
    }
    let head = parsed.map_err(|e| ExternalError::of_json(path, e))?;
    arrays.finish(head)
}

/// What the file says besides its samples.
struct Head {
    format: String,
    scene: String,
    code: Code,
    label: String,
    nodes: Vec<f64>,
}

/// The numbers read so far, and the first problem found (a serde error stops the parse, and
/// [`read`] reports this instead of it).
struct Arrays<'a> {
    path: &'a Path,
    values: usize,
    time: Vec<f64>,
    fields: [Option<Vec<f64>>; 2],
    row_len: [Option<usize>; 2],
    scalars: [Option<Vec<f64>>; 5],
    /// Which of [`SAMPLE_FIELDS`] sample 0 carries.
    first_sample: Option<[bool; 8]>,
    problem: Option<ExternalError>,
}

impl<'a> Arrays<'a> {
    fn new(path: &'a Path) -> Self {
        Self {
            path,
            values: 0,
            time: Vec::new(),
            fields: [None, None],
            row_len: [None, None],
            scalars: Default::default(),
            first_sample: None,
            problem: None,
        }
    }

    /// Records `problem` and returns the serde error that stops the parse.
    fn stop<E: de::Error>(&mut self, problem: ExternalError) -> E {
        self.problem.get_or_insert(problem);
        E::custom("stopped")
    }

    /// Counts one more number against [`MAX_VALUES`].
    fn count<E: de::Error>(&mut self, at: impl Fn() -> String) -> Result<(), E> {
        self.values += 1;
        if self.values > MAX_VALUES {
            let problem = ExternalError::invalid(
                self.path,
                "samples",
                Some(at()),
                format!("more than {MAX_VALUES} values"),
                format!("at most {MAX_VALUES} values in one file: sample fewer times or levels"),
            );
            return Err(self.stop(problem));
        }
        Ok(())
    }

    /// `x` when finite; otherwise the error naming `field` at `at`.
    fn finite<E: de::Error>(
        &mut self,
        field: &str,
        at: impl Fn() -> String,
        x: Option<f64>,
    ) -> Result<f64, E> {
        match x {
            Some(x) if x.is_finite() => Ok(x),
            _ => {
                let problem = ExternalError::invalid(
                    self.path,
                    field,
                    Some(at()),
                    "null (not a finite number)",
                    "a finite number: a run that went non-finite has no error norm",
                );
                Err(self.stop(problem))
            }
        }
    }

    /// The run: the head, the arrays, each row as long as the mesh.
    fn finish(self, head: Head) -> Result<ExternalRun, ExternalError> {
        let path = self.path;
        if head.format != FORMAT {
            return Err(ExternalError::invalid(
                path,
                "format",
                None,
                format!("{:?}", head.format),
                format!("{FORMAT:?}"),
            ));
        }
        if self.time.is_empty() {
            return Err(ExternalError::invalid(
                path,
                "samples",
                None,
                "none",
                "one sample per time step from t = 0 to the horizon",
            ));
        }
        let n = head.nodes.len();
        for (field, len) in FIELDS.iter().zip(self.row_len) {
            if let Some(len) = len.filter(|&len| len != n) {
                return Err(ExternalError::invalid(
                    path,
                    *field,
                    Some(SampleOrigin::Json.at(0)),
                    format!("{len} values"),
                    format!("one value per mesh node ({n})"),
                ));
            }
        }
        let [displacement, velocity] = self.fields;
        let [lambda, lambda_time, contact_displacement, energy, energy_time] = self.scalars;
        Ok(ExternalRun {
            path: path.to_path_buf(),
            origin: SampleOrigin::Json,
            scene: head.scene,
            code: head.code,
            label: head.label,
            nodes: head.nodes,
            time: self.time,
            displacement,
            velocity,
            lambda,
            lambda_time,
            contact_displacement,
            energy,
            energy_time,
        })
    }
}

/// The whole file: its head returned, its samples into the [`Arrays`].
struct RunSeed<'s, 'a>(&'s mut Arrays<'a>);

impl<'de> DeserializeSeed<'de> for RunSeed<'_, '_> {
    type Value = Head;

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Head, D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for RunSeed<'_, '_> {
    type Value = Head;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an external run: format, scene, code, label, mesh and samples")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Head, A::Error> {
        let arrays = self.0;
        let (mut format, mut scene, mut code, mut label, mut nodes) =
            (None, None, None, None, None);
        let mut samples = false;
        fn once<T, E: de::Error>(slot: &mut Option<T>, name: &'static str, v: T) -> Result<(), E> {
            match slot.replace(v) {
                Some(_) => Err(E::duplicate_field(name)),
                None => Ok(()),
            }
        }
        while let Some(key) = map.next_key::<Field>()? {
            match key {
                Field::Format => once(&mut format, "format", map.next_value()?)?,
                Field::Scene => once(&mut scene, "scene", map.next_value()?)?,
                Field::Code => once(&mut code, "code", map.next_value()?)?,
                Field::Label => once(&mut label, "label", map.next_value()?)?,
                Field::Mesh => once(&mut nodes, "mesh", map.next_value_seed(MeshSeed(arrays))?)?,
                Field::Samples => {
                    if samples {
                        return Err(de::Error::duplicate_field("samples"));
                    }
                    samples = true;
                    map.next_value_seed(SamplesSeed(arrays))?;
                }
            }
        }
        if !samples {
            return Err(de::Error::missing_field("samples"));
        }
        Ok(Head {
            format: format.ok_or_else(|| de::Error::missing_field("format"))?,
            scene: scene.ok_or_else(|| de::Error::missing_field("scene"))?,
            code: code.ok_or_else(|| de::Error::missing_field("code"))?,
            label: label.ok_or_else(|| de::Error::missing_field("label"))?,
            nodes: nodes.ok_or_else(|| de::Error::missing_field("mesh"))?,
        })
    }
}

/// `mesh`: `{"nodes": [...]}`.
struct MeshSeed<'s, 'a>(&'s mut Arrays<'a>);

impl<'de> DeserializeSeed<'de> for MeshSeed<'_, '_> {
    type Value = Vec<f64>;

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Vec<f64>, D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for MeshSeed<'_, '_> {
    type Value = Vec<f64>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a mesh: {\"nodes\": [x0, x1, …]}")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Vec<f64>, A::Error> {
        let arrays = self.0;
        let mut nodes = None;
        while let Some(MeshField::Nodes) = map.next_key::<MeshField>()? {
            if nodes.is_some() {
                return Err(de::Error::duplicate_field("nodes"));
            }
            let mut row = Vec::new();
            map.next_value_seed(RowSeed {
                arrays: &mut *arrays,
                field: "mesh.nodes",
                sample: None,
                out: &mut row,
            })?;
            nodes = Some(row);
        }
        nodes.ok_or_else(|| de::Error::missing_field("nodes"))
    }
}

/// `samples`: the array, each sample into the [`Arrays`].
struct SamplesSeed<'s, 'a>(&'s mut Arrays<'a>);

impl<'de> DeserializeSeed<'de> for SamplesSeed<'_, '_> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for SamplesSeed<'_, '_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array of samples")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let arrays = self.0;
        let mut k = 0;
        while seq
            .next_element_seed(SampleSeed {
                arrays: &mut *arrays,
                k,
            })?
            .is_some()
        {
            k += 1;
        }
        Ok(())
    }
}

/// Sample `k`: its numbers appended to the [`Arrays`].
struct SampleSeed<'s, 'a> {
    arrays: &'s mut Arrays<'a>,
    k: usize,
}

impl<'de> DeserializeSeed<'de> for SampleSeed<'_, '_> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for SampleSeed<'_, '_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a sample: {\"time\": t, …}")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let (arrays, k) = (self.arrays, self.k);
        let at = || SampleOrigin::Json.at(k);
        let mut seen = [false; 8];
        while let Some(field) = map.next_key::<SampleField>()? {
            let index = field as usize;
            if std::mem::replace(&mut seen[index], true) {
                return Err(de::Error::custom(format!(
                    "duplicate field in {}",
                    SampleOrigin::Json.at(k)
                )));
            }
            match field {
                SampleField::Time => {
                    let x = map.next_value::<Option<f64>>()?;
                    arrays.count(at)?;
                    let x = arrays.finite("time", at, x)?;
                    arrays.time.push(x);
                }
                SampleField::Displacement | SampleField::Velocity => {
                    let f = index - 1;
                    let mut row = arrays.fields[f].take().unwrap_or_default();
                    let before = row.len();
                    let appended = map.next_value_seed(RowSeed {
                        arrays: &mut *arrays,
                        field: FIELDS[f],
                        sample: Some(k),
                        out: &mut row,
                    });
                    let len = row.len() - before;
                    arrays.fields[f] = Some(row);
                    appended?;
                    match arrays.row_len[f] {
                        None if k == 0 => arrays.row_len[f] = Some(len),
                        Some(first) if first != len => {
                            let problem = ExternalError::invalid(
                                arrays.path,
                                FIELDS[f],
                                Some(at()),
                                format!("{len} values"),
                                format!("one value per mesh node ({first}): as many as samples[0]"),
                            );
                            return Err(arrays.stop(problem));
                        }
                        _ => {}
                    }
                }
                _ => {
                    let s = index - 3;
                    let x = map.next_value::<Option<f64>>()?;
                    arrays.count(at)?;
                    let x = arrays.finite(SCALARS[s], at, x)?;
                    arrays.scalars[s].get_or_insert_with(Vec::new).push(x);
                }
            }
        }
        if !seen[0] {
            return Err(de::Error::custom(format!(
                "missing field `time` in {}",
                SampleOrigin::Json.at(k)
            )));
        }
        match arrays.first_sample {
            None => arrays.first_sample = Some(seen),
            Some(first) => {
                if let Some(i) = (1..seen.len()).find(|&i| seen[i] != first[i]) {
                    let problem = inconsistent(arrays.path, SAMPLE_FIELDS[i], k, seen[i]);
                    return Err(arrays.stop(problem));
                }
            }
        }
        Ok(())
    }
}

/// A field that sample `k` has and sample 0 lacks (`here`), or the other way round.
fn inconsistent(path: &Path, field: &str, k: usize, here: bool) -> ExternalError {
    let (value, allowed) = if here {
        (
            "given",
            "absent, as in samples[0]: every sample carries the same fields",
        )
    } else {
        (
            "missing",
            "given, as in samples[0]: every sample carries the same fields",
        )
    };
    ExternalError::invalid(path, field, Some(SampleOrigin::Json.at(k)), value, allowed)
}

/// An array of numbers appended to `out`, each counted and checked finite.
struct RowSeed<'s, 'a, 'o> {
    arrays: &'s mut Arrays<'a>,
    field: &'static str,
    sample: Option<usize>,
    out: &'o mut Vec<f64>,
}

impl<'de> DeserializeSeed<'de> for RowSeed<'_, '_, '_> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for RowSeed<'_, '_, '_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "an array of numbers ({})", self.field)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let (arrays, field, sample) = (self.arrays, self.field, self.sample);
        let mut i = 0;
        while let Some(x) = seq.next_element::<Option<f64>>()? {
            let at = || match sample {
                Some(k) => format!("{}, node {i}", SampleOrigin::Json.at(k)),
                None => format!("node {i}"),
            };
            arrays.count(at)?;
            let x = arrays.finite(field, at, x)?;
            self.out.push(x);
            i += 1;
        }
        Ok(())
    }
}
