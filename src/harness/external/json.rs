//! The JSON form of an external run, read as a stream: every number goes from the file
//! straight into the flat arrays of the [`ExternalRun`] (no sample, row or text is held
//! whole), each checked finite as it comes and counted against [`MAX_VALUES`], every sample
//! checked to carry the fields sample 0 carries, each row as long as the first (and, at the
//! end, as the mesh). Unknown and duplicate fields are refused.
//!
//! Version 2 ([`Version::Two`]) lets `lambda`, `displacement` and `velocity` be `null` or absent
//! at any sample. The format may come after the samples: a departure from version 1's rules
//! met before it is kept, and is the file's error if the format then says version 1.
//!
//! Memory: the arrays, at most [`MAX_VALUES`] numbers of 8 bytes, grow by doubling, so reading
//! takes at most three times their final size, 384 MiB, whatever the file holds.

use std::fmt;
use std::path::Path;

use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;

use super::error::ExternalError;
use super::format::{
    parse_energy_definition, parse_mass, parse_scheme, Code, ExternalRun, SampleOrigin,
    SampledField, Version, MAX_VALUES, RUN_FILE,
};
use crate::harness::files::input;

/// The top-level fields.
#[derive(Deserialize)]
#[serde(field_identifier, rename_all = "snake_case")]
enum Field {
    Format,
    Scene,
    Code,
    Label,
    Scheme,
    Mass,
    Contact,
    EnergyDefinition,
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

/// The per-sample scalar fields besides `time` and `lambda`, in [`ExternalRun`]'s order.
const SCALARS: [&str; 4] = [
    "lambda_time",
    "contact_displacement",
    "energy",
    "energy_time",
];

/// The nodal fields.
const FIELDS: [&str; 2] = ["displacement", "velocity"];

/// The fields of [`SampleField`] that version 2 lets a sample leave null or absent.
const NULLABLE: [usize; 3] = [
    SampleField::Displacement as usize,
    SampleField::Velocity as usize,
    SampleField::Lambda as usize,
];

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
    scheme: Option<String>,
    mass: Option<String>,
    contact: Option<String>,
    energy_definition: Option<String>,
    nodes: Vec<f64>,
}

/// The numbers read so far, and the first problem found (a serde error stops the parse, and
/// [`read`] reports this instead of it).
struct Arrays<'a> {
    path: &'a Path,
    values: usize,
    /// The version, once `format` is read (unknown while a format that is neither).
    version: Option<Version>,
    /// The first departure from version 1's rules met before the format was read.
    deferred: Option<ExternalError>,
    time: Vec<f64>,
    fields: [Option<SampledField>; 2],
    /// Per field, its first row's length and sample.
    row_len: [Option<(usize, usize)>; 2],
    lambda: Option<Vec<Option<f64>>>,
    scalars: [Option<Vec<f64>>; 4],
    /// Which of [`SAMPLE_FIELDS`] sample 0 carries.
    first_sample: Option<[bool; 8]>,
    problem: Option<ExternalError>,
}

impl<'a> Arrays<'a> {
    fn new(path: &'a Path) -> Self {
        Self {
            path,
            values: 0,
            version: None,
            deferred: None,
            time: Vec::new(),
            fields: [None, None],
            row_len: [None, None],
            lambda: None,
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

    /// A departure from version 1's rules that version 2 allows (`problem` names it): the
    /// file's error in a version 1 file, nothing in a version 2 one, kept for
    /// [`Self::finish`] while the format is not read.
    fn v1_rule<E: de::Error>(&mut self, problem: impl FnOnce() -> ExternalError) -> Result<(), E> {
        match self.version {
            Some(Version::Two) => Ok(()),
            Some(Version::One) => Err(self.stop(problem())),
            None => {
                self.deferred.get_or_insert_with(problem);
                Ok(())
            }
        }
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
        let version = Version::parse(path, &head.format)?;
        if let (Version::One, Some(problem)) = (version, self.deferred) {
            return Err(problem);
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
            if let Some((len, k)) = len.filter(|&(len, _)| len != n) {
                return Err(ExternalError::invalid(
                    path,
                    *field,
                    Some(SampleOrigin::Json.at(k)),
                    format!("{len} values"),
                    format!("one value per mesh node ({n})"),
                ));
            }
        }
        let scheme = head.scheme.map(|s| parse_scheme(path, &s)).transpose()?;
        let mass = head.mass.map(|m| parse_mass(path, &m)).transpose()?;
        let energy_definition = head
            .energy_definition
            .map(|d| parse_energy_definition(path, &d))
            .transpose()?;
        let samples = self.time.len();
        let [displacement, velocity] = self.fields.map(|field| {
            field.map(|mut f| {
                f.finish(samples);
                f
            })
        });
        let lambda = self.lambda.map(|mut l| {
            l.resize(samples, None);
            l
        });
        let [lambda_time, contact_displacement, energy, energy_time] = self.scalars;
        Ok(ExternalRun {
            path: path.to_path_buf(),
            origin: SampleOrigin::Json,
            version,
            scene: head.scene,
            code: head.code,
            label: head.label,
            scheme,
            mass,
            contact: head.contact,
            energy_definition,
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
        let (mut scheme, mut mass, mut contact, mut energy_definition) = (None, None, None, None);
        let mut samples = false;
        fn once<T, E: de::Error>(slot: &mut Option<T>, name: &'static str, v: T) -> Result<(), E> {
            match slot.replace(v) {
                Some(_) => Err(E::duplicate_field(name)),
                None => Ok(()),
            }
        }
        while let Some(key) = map.next_key::<Field>()? {
            match key {
                Field::Format => {
                    let text: String = map.next_value()?;
                    arrays.version = Version::parse(arrays.path, &text).ok();
                    once(&mut format, "format", text)?
                }
                Field::Scene => once(&mut scene, "scene", map.next_value()?)?,
                Field::Code => once(&mut code, "code", map.next_value()?)?,
                Field::Label => once(&mut label, "label", map.next_value()?)?,
                Field::Scheme => once(&mut scheme, "scheme", map.next_value()?)?,
                Field::Mass => once(&mut mass, "mass", map.next_value()?)?,
                Field::Contact => once(&mut contact, "contact", map.next_value()?)?,
                Field::EnergyDefinition => once(
                    &mut energy_definition,
                    "energy_definition",
                    map.next_value()?,
                )?,
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
            scheme,
            mass,
            contact,
            energy_definition,
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
                    let mut field = arrays.fields[f].take();
                    let read = map.next_value_seed(FieldSeed {
                        arrays: &mut *arrays,
                        f,
                        k,
                        out: &mut field,
                    });
                    arrays.fields[f] = field;
                    read?;
                }
                SampleField::Lambda => {
                    let x = map.next_value::<Option<f64>>()?;
                    arrays.count(at)?;
                    let x = match x {
                        Some(x) => Some(arrays.finite("lambda", at, Some(x))?),
                        None => {
                            let path = arrays.path;
                            arrays.v1_rule(|| {
                                ExternalError::invalid(
                                    path,
                                    "lambda",
                                    Some(at()),
                                    "null (not a finite number)",
                                    "a finite number: a run that went non-finite has no error \
                                     norm (null, not computed, is read in signorini-external/2)",
                                )
                            })?;
                            None
                        }
                    };
                    let lambda = arrays.lambda.get_or_insert_with(Vec::new);
                    lambda.resize(k, None);
                    lambda.push(x);
                }
                _ => {
                    let s = index - 4;
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
                let path = arrays.path;
                for i in (1..seen.len()).filter(|&i| seen[i] != first[i]) {
                    let problem = || inconsistent(path, SAMPLE_FIELDS[i], k, seen[i]);
                    if NULLABLE.contains(&i) {
                        arrays.v1_rule(problem)?;
                    } else {
                        let problem = problem();
                        return Err(arrays.stop(problem));
                    }
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

/// Sample `k`'s row of the nodal field `f` (index in [`FIELDS`]) appended to `out`, as long as
/// the field's first row; `null` (version 2) leaves the sample without it.
struct FieldSeed<'s, 'a, 'o> {
    arrays: &'s mut Arrays<'a>,
    f: usize,
    k: usize,
    out: &'o mut Option<SampledField>,
}

impl<'de> DeserializeSeed<'de> for FieldSeed<'_, '_, '_> {
    type Value = ();

    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_option(self)
    }
}

impl<'de> Visitor<'de> for FieldSeed<'_, '_, '_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "an array of numbers ({}), or null", FIELDS[self.f])
    }

    fn visit_none<E: de::Error>(self) -> Result<(), E> {
        let (path, field, at) = (
            self.arrays.path,
            FIELDS[self.f],
            SampleOrigin::Json.at(self.k),
        );
        self.arrays.v1_rule(|| {
            ExternalError::invalid(
                path,
                field,
                Some(at),
                "null",
                "one number per mesh node (null, not computed, is read in signorini-external/2)",
            )
        })
    }

    fn visit_some<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        let (arrays, f, k) = (self.arrays, self.f, self.k);
        let row = self
            .out
            .get_or_insert_with(SampledField::default)
            .begin_row(k);
        let before = row.len();
        RowSeed {
            arrays: &mut *arrays,
            field: FIELDS[f],
            sample: Some(k),
            out: row,
        }
        .deserialize(d)?;
        let len = row.len() - before;
        match arrays.row_len[f] {
            None => arrays.row_len[f] = Some((len, k)),
            Some((first, j)) if first != len => {
                let problem = ExternalError::invalid(
                    arrays.path,
                    FIELDS[f],
                    Some(SampleOrigin::Json.at(k)),
                    format!("{len} values"),
                    format!(
                        "one value per mesh node ({first}): as many as {}",
                        SampleOrigin::Json.at(j)
                    ),
                );
                return Err(arrays.stop(problem));
            }
            _ => {}
        }
        Ok(())
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::fem::MassVariant;
    use crate::harness::external::format::EnergyDefinition;

    /// `text` written as `name` into a scratch directory, then read.
    fn read_text(name: &str, text: &str) -> Result<ExternalRun, ExternalError> {
        let dir = std::env::temp_dir().join(format!("signorini-json-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        read(&path)
    }

    /// A version 2 file: λ null at t = 0, the fields at the last sample only.
    const V2: &str = r#"{
  "format": "signorini-external/2",
  "scene": "bar1d-dirichlet",
  "code": { "name": "test", "version": "0" },
  "label": "v2",
  "mass": "standard",
  "mesh": { "nodes": [0, 0.5, 1] },
  "samples": [
    { "time": 0, "lambda": null, "velocity": null },
    { "time": 1.5, "lambda": -0.5 },
    { "time": 3, "displacement": [0.5, 0.25, 0], "velocity": [0, 0, 0], "lambda": 0 }
  ]
}"#;

    fn field_and_place(result: Result<ExternalRun, ExternalError>) -> (String, Option<String>) {
        match result {
            Err(ExternalError::Invalid { field, at, .. }) => (field, at),
            other => panic!("expected an invalid field, got {other:?}"),
        }
    }

    #[test]
    fn version_2_reads_null_multipliers_and_fields_at_some_samples() {
        let run = read_text("v2.json", V2).unwrap();
        assert_eq!(run.version, Version::Two);
        assert_eq!(run.mass, Some(MassVariant::Standard));
        assert_eq!(run.lambda, Some(vec![None, Some(-0.5), Some(0.0)]));
        for field in [&run.displacement, &run.velocity] {
            let f = field.as_ref().unwrap();
            assert_eq!((f.sampled(), f.is_complete()), (1, false));
        }
        assert_eq!(run.row(&run.displacement, 0), None);
        assert_eq!(run.row(&run.displacement, 2), Some(&[0.5, 0.25, 0.0][..]));
        assert_eq!(run.contact_displacement_at(1), None);
        assert_eq!(run.contact_displacement_at(2), Some(0.5));
    }

    /// What version 2 allows is refused in a version 1 file, whether its format comes before
    /// the samples (refused as met) or after them (refused once the format is read).
    #[test]
    fn version_1_refuses_null_wherever_its_format_stands() {
        let v1 = V2
            .replace("external/2", "external/1")
            .replace("\"mass\": \"standard\",", "");
        let format_last = v1
            .replace("\"format\": \"signorini-external/1\",", "")
            .replace(
                "\n  ]\n}",
                "\n  ],\n  \"format\": \"signorini-external/1\"\n}",
            );
        for (name, text) in [("first.json", &v1), ("last.json", &format_last)] {
            let expected = ("lambda".to_string(), Some("samples[0]".to_string()));
            assert_eq!(field_and_place(read_text(name, text)), expected, "{name}");
        }
    }

    #[test]
    fn declarations_are_refused_naming_the_allowed_values() {
        let bad_mass = V2.replace("\"standard\"", "\"heavy\"");
        let message = read_text("mass.json", &bad_mass).unwrap_err().to_string();
        assert!(
            message.contains("invalid mass = \"heavy\"") && message.contains("redistributed"),
            "{message}"
        );
        let bad_definition = V2.replace(
            "\"mass\": \"standard\",",
            "\"energy_definition\": \"kinetic\",",
        );
        let message = read_text("definition.json", &bad_definition)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("invalid energy_definition = \"kinetic\"")
                && message.contains(EnergyDefinition::NAMES),
            "{message}"
        );
        let short = V2.replace("[0.5, 0.25, 0]", "[0.5, 0.25]");
        let expected = ("displacement".to_string(), Some("samples[2]".to_string()));
        assert_eq!(field_and_place(read_text("short.json", &short)), expected);
    }
}
