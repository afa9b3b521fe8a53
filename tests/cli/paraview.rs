//! A box run opens in ParaView as one scene: `fields.pvd` lists every VTK snapshot with its time
//! (and the obstacle beside it), `obstacle.vtu` is the plane `x_d = −gap` a little wider than
//! the box, in 2D and 3D; without an obstacle there is no `obstacle.vtu`; both count among the
//! files of `--max-files` and belong to the run directory a new run replaces.

use crate::common;

use std::path::{Path, PathBuf};

use common::{expect_error, signorini, success_stdout};
use signorini::harness::run::paraview::OBSTACLE_MARGIN;
use vtkio::model::{DataSet, Piece};
use vtkio::Vtk;

/// The obstacle of the committed box scenes: 0.2 below the contact face.
const GAP: f64 = 0.2;
/// The width (and, in 3D, the depth) of the committed box scenes.
const WIDTH: f64 = 0.1;

/// A fresh, absent output directory named after `name`.
fn out_dir(name: &str) -> PathBuf {
    let out = std::env::temp_dir().join(format!("signorini-pvd-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    out
}

/// `run SCENE` with Crank–Nicolson and the redistributed mass on `nx` elements into `out`, plus
/// `extra`.
fn run_args(scene: &str, nx: &str, out: &Path, extra: &[&str]) -> Vec<String> {
    let out = out.to_string_lossy().into_owned();
    let mut args: Vec<String> = [
        "run",
        scene,
        "--scheme",
        "crank-nicolson",
        "--mass",
        "redistributed",
        "--nx",
        nx,
        "--out",
        &out,
    ]
    .map(String::from)
    .to_vec();
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

/// Runs `args`, which must succeed.
fn run_ok(args: &[String]) {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    success_stdout(&signorini(&args));
}

/// One `<DataSet>` of a collection.
#[derive(Debug, PartialEq)]
struct DataSetEntry {
    time: f64,
    part: String,
    file: String,
}

/// The datasets of the collection `path`, checked to be a VTK `Collection` file.
fn collection(path: &Path) -> Vec<DataSetEntry> {
    let text = std::fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let root = doc.root_element();
    assert!(root.has_tag_name("VTKFile"));
    assert_eq!(root.attribute("type"), Some("Collection"));
    let collections: Vec<_> = root
        .children()
        .filter(|n| n.has_tag_name("Collection"))
        .collect();
    assert_eq!(collections.len(), 1);
    collections[0]
        .children()
        .filter(|n| n.is_element())
        .map(|n| {
            assert!(n.has_tag_name("DataSet"), "{:?}", n.tag_name());
            DataSetEntry {
                time: n.attribute("timestep").unwrap().parse().unwrap(),
                part: n.attribute("part").unwrap().to_string(),
                file: n.attribute("file").unwrap().to_string(),
            }
        })
        .collect()
}

/// The names of the snapshots `field-t<T>.vtu` in `dir`.
fn snapshot_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("field-t") && n.ends_with(".vtu"))
        .collect();
    names.sort();
    names
}

/// Checks the collection of the run in `out`: the snapshots as part 0, each time once and in
/// increasing order, named after their time rounded to the step (`field-t0.500.vtu`) so that
/// their names sort in time order, exactly the snapshot files of `out`, at `times`;
/// with `obstacle`, `obstacle.vtu` as part 1 at every time; every file listed exists.
fn check_collection(out: &Path, times: &[f64], obstacle: bool) {
    let entries = collection(&out.join("fields.pvd"));
    let snapshots: Vec<&DataSetEntry> = entries.iter().filter(|e| e.part == "0").collect();
    let listed: Vec<f64> = snapshots.iter().map(|e| e.time).collect();
    assert_eq!(listed, times);
    for s in &snapshots {
        let named = s
            .file
            .strip_prefix("field-t")
            .and_then(|n| n.strip_suffix(".vtu"));
        let named = named.unwrap_or_else(|| panic!("{}", s.file));
        let decimals = named.split_once('.').map_or(0, |(_, d)| d.len());
        let time: f64 = named.parse().unwrap();
        assert!(decimals >= 1, "{}", s.file);
        assert!(
            (time - s.time).abs() <= 0.5 * 10f64.powi(-(decimals as i32)),
            "{} at t = {}",
            s.file,
            s.time
        );
    }
    let in_time_order: Vec<String> = snapshots.iter().map(|e| e.file.clone()).collect();
    let mut files = in_time_order.clone();
    files.sort();
    assert_eq!(files, in_time_order, "the names do not sort in time order");
    assert_eq!(files, snapshot_files(out));
    let obstacles: Vec<&DataSetEntry> = entries.iter().filter(|e| e.part == "1").collect();
    if obstacle {
        assert_eq!(obstacles.iter().map(|e| e.time).collect::<Vec<_>>(), times);
        assert!(obstacles.iter().all(|e| e.file == "obstacle.vtu"));
    } else {
        assert!(obstacles.is_empty(), "{obstacles:?}");
    }
    assert_eq!(entries.len(), snapshots.len() + obstacles.len());
    for e in &entries {
        assert!(out.join(&e.file).is_file(), "{} listed, absent", e.file);
    }
}

/// The points (as `[x, y, z]`) and the VTK cell types of the unstructured grid `path`; its
/// `Piece`'s counts checked against them.
fn grid(path: &Path) -> (Vec<[f64; 3]>, Vec<u8>) {
    let text = std::fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let piece = doc.descendants().find(|n| n.has_tag_name("Piece")).unwrap();
    let count = |name: &str| -> usize { piece.attribute(name).unwrap().parse().unwrap() };
    let vtk = Vtk::import(path).unwrap();
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("{} is not an unstructured grid", path.display());
    };
    let [Piece::Inline(piece_data)] = &pieces[..] else {
        panic!("{}: not one inline piece", path.display());
    };
    let coordinates: Vec<f64> = piece_data.points.cast_into().unwrap();
    let points: Vec<[f64; 3]> = coordinates
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let types: Vec<u8> = piece_data.cells.types.iter().map(|t| *t as u8).collect();
    assert_eq!(points.len(), count("NumberOfPoints"));
    assert_eq!(types.len(), count("NumberOfCells"));
    (points, types)
}

/// Checks `obstacle.vtu` of a box of `dim` dimensions: one cell (a line in 2D, VTK 3; a quad in
/// 3D, VTK 9) on the plane `x_d = −gap`, spanning the box's cross-section plus the margin on
/// each side.
fn check_obstacle(out: &Path, dim: usize) {
    let (points, types) = grid(&out.join("obstacle.vtu"));
    let (n, cell) = if dim == 2 { (2, 3) } else { (4, 9) };
    assert_eq!(types, [cell]);
    assert_eq!(points.len(), n);
    let (low, high) = (-OBSTACLE_MARGIN * WIDTH, (1.0 + OBSTACLE_MARGIN) * WIDTH);
    for p in &points {
        assert!((p[dim - 1] + GAP).abs() < 1e-15, "{p:?} off x_d = -gap");
        for &x in &p[..dim - 1] {
            assert!(
                (x - low).abs() < 1e-15 || (x - high).abs() < 1e-15,
                "{p:?} not at a corner"
            );
        }
        if dim == 2 {
            assert_eq!(p[2], 0.0);
        }
    }
    let mut corners: Vec<[u64; 3]> = points.iter().map(|p| p.map(f64::to_bits)).collect();
    corners.sort_unstable();
    corners.dedup();
    assert_eq!(corners.len(), n, "repeated corners {points:?}");
}

#[test]
fn a_2d_box_run_is_one_paraview_time_series_with_the_obstacle_line() {
    let out = out_dir("2d");
    let args = run_args("scenes/bar2d.json", "10", &out, &[]);
    run_ok(&args);
    check_collection(&out, &[0.5, 1.0, 1.5, 2.0], true);
    check_obstacle(&out, 2);
    run_ok(&args);
    check_collection(&out, &[0.5, 1.0, 1.5, 2.0], true);
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn a_3d_box_run_is_one_paraview_time_series_with_the_obstacle_quad() {
    let out = out_dir("3d");
    run_ok(&run_args("scenes/bar3d.json", "4", &out, &[]));
    check_collection(&out, &[0.5, 1.0, 1.5, 2.0], true);
    check_obstacle(&out, 3);
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn without_an_obstacle_the_collection_lists_the_snapshots_alone_each_once_in_time_order() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/bar2d.json")).unwrap();
    let (gap, times) = (
        "\"obstacle\": { \"gap\": 0.2 },",
        "\"fields_at\": [0.5, 1.0, 1.5, 2.0]",
    );
    assert!(text.contains(gap) && text.contains(times));
    let edited =
        text.replacen(gap, "", 1)
            .replacen(times, "\"fields_at\": [1.5, 0.25, 1.5, 0.0]", 1);
    let out = out_dir("free");
    let scene = out.with_extension("json");
    std::fs::write(&scene, edited).unwrap();
    run_ok(&run_args(&scene.to_string_lossy(), "10", &out, &[]));
    check_collection(&out, &[0.0, 0.25, 1.5], false);
    assert!(!out.join("obstacle.vtu").exists());
    std::fs::remove_dir_all(&out).unwrap();
    std::fs::remove_file(&scene).unwrap();
}

#[test]
fn the_collection_and_the_obstacle_count_among_the_files_written() {
    let out = out_dir("budget");
    let args = run_args("scenes/bar2d.json", "10", &out, &["--max-files", "8"]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    expect_error(&args, 2, &["9 files", "8 files", "--max-files"]);
    assert!(!out.exists());
    run_ok(&run_args(
        "scenes/bar2d.json",
        "10",
        &out,
        &["--max-files", "9"],
    ));
    let written = std::fs::read_dir(&out)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().file_name() != ".signorini-manifest.json")
        .count();
    assert_eq!(written, 9);
    std::fs::remove_dir_all(&out).unwrap();
}
