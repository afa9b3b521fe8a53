//! Another code's box run as XDMF holds it (eXtensible Data Model and Format, version 3): an
//! XML file (`.xdmf`) of grids, each with its geometry, its time and its nodal attributes,
//! whose values (the heavy data) sit in an HDF5 file beside it or inline in the XML. Two
//! writers were tried (their files are committed in `tests/data/external/`):
//!
//! - **DOLFINx's `XDMFFile`** (0.5.2): the mesh once, as a grid of its own, then one temporal
//!   collection per function, whose grids include the mesh's topology and geometry
//!   (`xi:include`) and hold that function at one time (`/Function/<name>/<time>` in the HDF5
//!   file);
//! - **legacy FEniCS's `XDMFFile`** (dolfin 2019.2 with `functions_share_mesh`): one temporal
//!   collection whose first grid holds the mesh and every later one includes it, each holding
//!   every function at its time (`/VisualisationVector/<k>`).
//!
//! Both are read the same way: every uniform grid with a `Time` gives its nodal attributes
//! (`Center="Node"`) to the snapshot of that time; a grid without geometry of its own takes the
//! document's first (what the inclusions point to), and so does its topology: a
//! `Triangle`, `Quadrilateral`, `Tetrahedron` or `Hexahedron` topology's connectivity is read
//! (integer heavy data, one row of the cell's vertices per cell) and given to every snapshot as
//! its cells ([`Topology::Cells`], with the VTK type of that element); any other type is given by
//! its name ([`Topology::Declared`]), for the box run's reader to refuse. The writers' empty document type
//! declaration (`<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>`) is allowed; `roxmltree` bounds what a
//! declaration's entities expand to. Every snapshot must have the same geometry
//! (a mesh that moves or changes is refused). Heavy data are read by the pure-Rust HDF5 decoder
//! `hdf5-reader`: `Float32` or `Float64` datasets, their sizes checked against
//! [`MAX_VALUES`] before they are read.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use hdf5_reader::dataset::Dataset;
use hdf5_reader::datatype_api::H5Type;
use hdf5_reader::{Datatype, Hdf5File, OpenOptions};

use super::error::{unquoted, ExternalError};
use super::format::{MAX_VALUES, RUN_FILE};
use super::mesh::{CellKind, Cells, Topology};
use super::nodal_snapshot::{epsilon_of, NodalSnapshot, PointArray};
use super::xml_depth::check_depth;
use crate::harness::files::input::read_bytes;

/// What the reader takes, for its errors.
const XDMF: &str = "an XDMF 3 file (.xdmf) of uniform grids with a Time, an XY or XYZ \
                    Geometry and nodal Attributes, their DataItems in HDF5 (Format=\"HDF\", \
                    Float32 or Float64) or inline (Format=\"XML\")";

/// How deep grids may nest (a temporal collection of uniform grids is two levels; XDMF's
/// spatial collections add one).
const MAX_GRID_DEPTH: usize = 8;

/// Where a data item's values are.
#[derive(Debug, Clone, PartialEq)]
enum Values {
    /// A dataset of an HDF5 file.
    Hdf5 {
        /// The HDF5 file, resolved against the XDMF file's directory.
        file: PathBuf,
        /// The dataset's path in it.
        dataset: String,
    },
    /// Numbers written in the XML itself.
    Inline(Vec<f64>),
}

/// A `DataItem`: its values and its `Dimensions`.
#[derive(Debug, Clone, PartialEq)]
struct DataItem {
    values: Values,
    dimensions: Vec<usize>,
}

impl DataItem {
    /// Values per node: the last dimension of a two-dimensional item, else 1.
    fn components(&self) -> usize {
        match self.dimensions.as_slice() {
            [_, c] => *c,
            _ => 1,
        }
    }

    /// The number of nodes it holds: its first dimension.
    fn nodes(&self) -> usize {
        self.dimensions.first().copied().unwrap_or(0)
    }
}

/// A nodal attribute of one time.
#[derive(Debug, Clone, PartialEq)]
struct NodalAttribute {
    name: String,
    item: DataItem,
}

/// An XDMF file's run: one geometry, and per time its nodal attributes.
#[derive(Debug, Clone, PartialEq)]
pub struct XdmfSeries {
    path: PathBuf,
    geometry: DataItem,
    /// The `TopologyType` of the document's first topology and its connectivity, if it has one.
    topology: Option<(String, Option<DataItem>)>,
    /// Per time (increasing): the time and its attributes.
    times: Vec<(f64, Vec<NodalAttribute>)>,
}

impl XdmfSeries {
    /// Reads the XML of `path` (its heavy data are read by [`XdmfSeries::snapshot`]).
    pub fn read(path: &Path) -> Result<Self, ExternalError> {
        let bytes = read_bytes(path, RUN_FILE)?;
        let invalid =
            |field: &str, value: String| ExternalError::invalid(path, field, None, value, XDMF);
        let text =
            String::from_utf8(bytes).map_err(|_| invalid("file", "not UTF-8 text".into()))?;
        check_depth(path, text.as_bytes())?;
        let options = roxmltree::ParsingOptions {
            allow_dtd: true,
            ..roxmltree::ParsingOptions::default()
        };
        let document = roxmltree::Document::parse_with_options(&text, options)
            .map_err(|e| invalid("file", format!("malformed XML ({})", unquoted(e))))?;
        let root = document.root_element();
        if root.tag_name().name() != "Xdmf" {
            return Err(invalid(
                "root element",
                format!("<{}>", root.tag_name().name()),
            ));
        }
        let domain = root
            .children()
            .find(|n| n.has_tag_name("Domain"))
            .ok_or_else(|| invalid("Domain", "missing".into()))?;
        let directory = path.parent().unwrap_or(Path::new("."));
        let mut walk = Walk {
            path,
            directory,
            geometry: None,
            topology: None,
            by_time: BTreeMap::new(),
        };
        for grid in domain.children().filter(|n| n.has_tag_name("Grid")) {
            walk.grid(grid, 1)?;
        }
        let geometry = walk
            .geometry
            .ok_or_else(|| invalid("Geometry", "none".into()))?;
        if walk.by_time.is_empty() {
            return Err(invalid("Time", "no grid with a Time".into()));
        }
        let times = walk.by_time.into_values().collect();
        Ok(Self {
            path: path.to_path_buf(),
            geometry,
            topology: walk.topology,
            times,
        })
    }

    /// The times, increasing.
    pub fn times(&self) -> Vec<f64> {
        self.times.iter().map(|(t, _)| *t).collect()
    }

    /// The snapshot of time `n`: the geometry's points (padded to three coordinates) and the
    /// time's nodal attributes, each read from its heavy data.
    pub fn snapshot(&self, n: usize) -> Result<NodalSnapshot, ExternalError> {
        let (points, single) = self.values(&self.geometry, "Geometry")?;
        let d = self.geometry.components();
        if !(1..=3).contains(&d) || points.len() != d * self.geometry.nodes() {
            return Err(ExternalError::invalid(
                &self.path,
                "Geometry",
                None,
                format!("{} values of {} coordinates", points.len(), d),
                "one to three coordinates per node, as its Dimensions say",
            ));
        }
        let coordinates: Vec<f64> = points
            .chunks_exact(d)
            .flat_map(|p| (0..3).map(move |c| p.get(c).copied().unwrap_or(0.0)))
            .collect();
        let (time, attributes) = &self.times[n];
        let mut arrays = Vec::with_capacity(attributes.len());
        for attribute in attributes {
            let field = format!("Attribute {:?}", attribute.name);
            let (values, single) = self.values(&attribute.item, &field)?;
            if attribute.item.nodes() != self.geometry.nodes() {
                return Err(ExternalError::invalid(
                    &self.path,
                    field,
                    Some(format!("Time {time}")),
                    format!("{} nodes", attribute.item.nodes()),
                    format!(
                        "one value per node of the geometry ({})",
                        self.geometry.nodes()
                    ),
                ));
            }
            arrays.push(PointArray {
                name: attribute.name.clone(),
                components: attribute.item.components(),
                values,
                epsilon: epsilon_of(single),
            });
        }
        let topology = self.cells()?;
        NodalSnapshot::new(
            &self.path,
            coordinates,
            epsilon_of(single),
            arrays,
            topology,
        )
    }

    /// The topology's cells: its connectivity read when its type is an element the harness
    /// interpolates, one row of that element's vertices per cell; its name otherwise.
    fn cells(&self) -> Result<Option<Topology>, ExternalError> {
        let Some((name, item)) = &self.topology else {
            return Ok(None);
        };
        let (Some(kind), Some(item)) = (CellKind::of_xdmf(name), item) else {
            return Ok(Some(Topology::Declared(name.clone())));
        };
        let (values, _) = self.values(item, "Topology")?;
        let n = kind.vertices();
        let nodes = self.geometry.nodes();
        let invalid = |value: String, allowed: String| {
            ExternalError::invalid(&self.path, "Topology", None, value, allowed)
        };
        if item.components() != n || values.len() % n != 0 {
            return Err(invalid(
                format!("rows of {} vertices", item.components()),
                format!("one row of {n} vertices per {}", kind.name()),
            ));
        }
        let mut cells = Cells::default();
        for row in values.chunks_exact(n) {
            let vertices = row
                .iter()
                .map(|&v| {
                    (v >= 0.0 && v.fract() == 0.0 && v < nodes as f64)
                        .then_some(v as usize)
                        .ok_or_else(|| {
                            invalid(v.to_string(), format!("a node of the geometry's {nodes}"))
                        })
                })
                .collect::<Result<Vec<usize>, _>>()?;
            cells.push(kind.vtk(), &vertices);
        }
        Ok(Some(Topology::Cells(cells)))
    }

    /// The values of `item` (`field`, for errors) as `f64`, and whether they were single
    /// precision.
    fn values(&self, item: &DataItem, field: &str) -> Result<(Vec<f64>, bool), ExternalError> {
        match &item.values {
            Values::Inline(values) => Ok((values.clone(), false)),
            Values::Hdf5 { file, dataset } => read_dataset(file, dataset, &item.dimensions)
                .map_err(|problem| {
                    ExternalError::invalid(
                        file,
                        format!("{field} dataset {dataset:?}"),
                        None,
                        problem,
                        "a Float32 or Float64 dataset (integers for a topology) of the \
                         DataItem's Dimensions, at most 2^24 values",
                    )
                }),
        }
    }
}

/// Reads `dataset` of the HDF5 file `file`, checked to have `dimensions` (which
/// [`Walk::data_item`] bounded by [`MAX_VALUES`] values) before it is read; the values as `f64` and whether they were `f32`.
fn read_dataset(
    file: &Path,
    dataset: &str,
    dimensions: &[usize],
) -> Result<(Vec<f64>, bool), String> {
    let options = OpenOptions::default().with_max_read_bytes(MAX_VALUES * 8);
    let hdf5 = Hdf5File::open_with_options(file, options)
        .map_err(|e| format!("unreadable ({})", unquoted(e)))?;
    let data = hdf5
        .dataset(dataset)
        .map_err(|e| format!("not found ({})", unquoted(e)))?;
    let shape: Vec<usize> = data.shape().iter().map(|&s| s as usize).collect();
    if shape != dimensions {
        return Err(format!(
            "of shape {shape:?} where the DataItem says {dimensions:?}"
        ));
    }
    match data.dtype() {
        Datatype::FloatingPoint { size: 8, .. } => data
            .read_array::<f64>()
            .map(|a| (a.iter().copied().collect(), false))
            .map_err(|e| format!("unreadable ({})", unquoted(e))),
        Datatype::FloatingPoint { size: 4, .. } => data
            .read_array::<f32>()
            .map(|a| (a.iter().map(|&x| f64::from(x)).collect(), true))
            .map_err(|e| format!("unreadable ({})", unquoted(e))),
        Datatype::FixedPoint { size, signed, .. } => match (size, signed) {
            (1, true) => integers::<i8>(&data, f64::from),
            (1, false) => integers::<u8>(&data, f64::from),
            (2, true) => integers::<i16>(&data, f64::from),
            (2, false) => integers::<u16>(&data, f64::from),
            (4, true) => integers::<i32>(&data, f64::from),
            (4, false) => integers::<u32>(&data, f64::from),
            (8, true) => integers::<i64>(&data, |x| x as f64),
            (8, false) => integers::<u64>(&data, |x| x as f64),
            _ => Err(format!("of integers of {size} bytes")),
        },
        other => Err(format!("of type {other:?}")),
    }
}

/// The integers of type `T` of `data`, each as `f64` by `to` (exact below 2⁵³, beyond any
/// node's number).
fn integers<T: H5Type + Copy>(
    data: &Dataset,
    to: fn(T) -> f64,
) -> Result<(Vec<f64>, bool), String> {
    data.read_array::<T>()
        .map(|a| (a.iter().map(|&x| to(x)).collect(), false))
        .map_err(|e| format!("unreadable ({})", unquoted(e)))
}

/// The walk through an XDMF document's grids.
struct Walk<'a> {
    path: &'a Path,
    directory: &'a Path,
    /// The document's first geometry: what a grid without one of its own includes.
    geometry: Option<DataItem>,
    /// The `TopologyType` of the document's first topology (`Type`, XDMF 2's name, when it has
    /// no `TopologyType`) and its connectivity, when it has a `DataItem`.
    topology: Option<(String, Option<DataItem>)>,
    /// Per time (by its bits, so that equal times meet): the time and the nodal attributes its
    /// grids hold.
    by_time: BTreeMap<TimeKey, (f64, Vec<NodalAttribute>)>,
}

/// A time as a map key, ordered as the number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct TimeKey(i64);

impl TimeKey {
    /// The key of `t` (finite): IEEE 754's total order, as an integer.
    fn of(t: f64) -> Self {
        let bits = t.to_bits() as i64;
        Self(bits ^ (((bits >> 63) as u64) >> 1) as i64)
    }
}

impl Walk<'_> {
    fn invalid(
        &self,
        field: &str,
        at: Option<String>,
        value: impl std::fmt::Display,
    ) -> ExternalError {
        ExternalError::invalid(self.path, field, at, value, XDMF)
    }

    /// Reads `grid` (at nesting `depth`): a collection's grids in turn, or a uniform grid's
    /// geometry, time and nodal attributes.
    fn grid(&mut self, grid: roxmltree::Node<'_, '_>, depth: usize) -> Result<(), ExternalError> {
        let name = grid.attribute("Name").unwrap_or("");
        let at = || Some(format!("Grid {name:?}"));
        if depth > MAX_GRID_DEPTH {
            return Err(self.invalid("Grid", at(), format!("nested deeper than {MAX_GRID_DEPTH}")));
        }
        match grid.attribute("GridType").unwrap_or("Uniform") {
            "Collection" | "Tree" => {
                for child in grid.children().filter(|n| n.has_tag_name("Grid")) {
                    self.grid(child, depth + 1)?;
                }
                Ok(())
            }
            "Uniform" => self.uniform(grid),
            other => Err(self.invalid("GridType", at(), format!("{other:?}"))),
        }
    }

    /// A uniform grid: its geometry (its own, else the document's first, which every grid with
    /// a `Time` must have), and, when it has a `Time`, its nodal attributes at that time.
    fn uniform(&mut self, grid: roxmltree::Node<'_, '_>) -> Result<(), ExternalError> {
        let name = grid.attribute("Name").unwrap_or("");
        let at = || Some(format!("Grid {name:?}"));
        let own = match grid.children().find(|n| n.has_tag_name("Geometry")) {
            Some(geometry) => {
                let kind = geometry.attribute("GeometryType").unwrap_or("XYZ");
                if !matches!(kind, "XY" | "XYZ") {
                    return Err(self.invalid("GeometryType", at(), format!("{kind:?}")));
                }
                Some(self.data_item(geometry, at)?)
            }
            None => None,
        };
        if self.geometry.is_none() {
            self.geometry.clone_from(&own);
        }
        if self.topology.is_none() {
            if let Some(topology) = grid.children().find(|n| n.has_tag_name("Topology")) {
                let kind = topology
                    .attribute("TopologyType")
                    .or(topology.attribute("Type"));
                let item = match topology.children().any(|n| n.has_tag_name("DataItem")) {
                    true => Some(self.data_item(topology, at)?),
                    false => None,
                };
                self.topology = Some((kind.unwrap_or("").to_string(), item));
            }
        }
        let Some(time) = grid.children().find(|n| n.has_tag_name("Time")) else {
            return Ok(());
        };
        let value = time.attribute("Value").unwrap_or("");
        let t: f64 = value
            .trim()
            .parse()
            .ok()
            .filter(|t: &f64| t.is_finite())
            .ok_or_else(|| self.invalid("Time.Value", at(), format!("{value:?}")))?;
        if self.geometry.is_none() {
            return Err(self.invalid("Geometry", at(), "none before this grid"));
        }
        if own.is_some() && own != self.geometry {
            return Err(ExternalError::invalid(
                self.path,
                "Geometry",
                at(),
                format!("another geometry at Time {t}"),
                "one mesh for every time (a mesh that moves or changes is not read)",
            ));
        }
        let mut attributes = Vec::new();
        for attribute in grid.children().filter(|n| n.has_tag_name("Attribute")) {
            if attribute.attribute("Center").unwrap_or("Node") != "Node" {
                continue;
            }
            let attribute_name = attribute.attribute("Name").unwrap_or("").to_string();
            let item = self.data_item(attribute, at)?;
            attributes.push(NodalAttribute {
                name: attribute_name,
                item,
            });
        }
        let entry = self
            .by_time
            .entry(TimeKey::of(t))
            .or_insert_with(|| (t, Vec::new()));
        for attribute in attributes {
            if entry.1.iter().any(|a| a.name == attribute.name) {
                return Err(self.invalid(
                    "Attribute",
                    at(),
                    format!("{:?} twice at Time {t}", attribute.name),
                ));
            }
            entry.1.push(attribute);
        }
        Ok(())
    }

    /// The `DataItem` child of `parent`: its `Dimensions` and where its values are.
    fn data_item(
        &self,
        parent: roxmltree::Node<'_, '_>,
        at: impl Fn() -> Option<String>,
    ) -> Result<DataItem, ExternalError> {
        let item = parent
            .children()
            .find(|n| n.has_tag_name("DataItem"))
            .ok_or_else(|| self.invalid("DataItem", at(), "missing"))?;
        let dimensions: Vec<usize> = item
            .attribute("Dimensions")
            .unwrap_or("")
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .ok()
            .filter(|d: &Vec<usize>| (1..=2).contains(&d.len()))
            .ok_or_else(|| {
                self.invalid(
                    "DataItem.Dimensions",
                    at(),
                    format!("{:?}", item.attribute("Dimensions").unwrap_or("")),
                )
            })?;
        let count = dimensions.iter().try_fold(1usize, |a, &b| a.checked_mul(b));
        if count.is_none_or(|c| c > MAX_VALUES) {
            return Err(self.invalid(
                "DataItem.Dimensions",
                at(),
                format!("{dimensions:?}: too many values"),
            ));
        }
        if item.attribute("ItemType").is_some_and(|t| t != "Uniform") {
            return Err(self.invalid(
                "DataItem.ItemType",
                at(),
                format!("{:?}", item.attribute("ItemType").unwrap_or("")),
            ));
        }
        let text = item.text().unwrap_or("").trim();
        let values = match item.attribute("Format").unwrap_or("XML") {
            "HDF" => {
                let (file, dataset) = text
                    .split_once(":/")
                    .filter(|(f, _)| !f.is_empty())
                    .ok_or_else(|| self.invalid("DataItem", at(), "no FILE:/DATASET"))?;
                Values::Hdf5 {
                    file: self.directory.join(file),
                    dataset: format!("/{dataset}"),
                }
            }
            "XML" => {
                let values: Vec<f64> = text
                    .split_whitespace()
                    .map(str::parse)
                    .collect::<Result<_, _>>()
                    .map_err(|_| {
                        self.invalid("DataItem", at(), "inline values that are not numbers")
                    })?;
                if Some(values.len()) != count {
                    return Err(self.invalid(
                        "DataItem",
                        at(),
                        format!(
                            "{} inline values for Dimensions {dimensions:?}",
                            values.len()
                        ),
                    ));
                }
                Values::Inline(values)
            }
            other => return Err(self.invalid("DataItem.Format", at(), format!("{other:?}"))),
        };
        Ok(DataItem { values, dimensions })
    }
}
