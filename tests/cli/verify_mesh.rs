//! `signorini verify` reads a box run's cells (issue 57): the harness's own 2D and 3D runs,
//! their cells rewritten here, are refused when the cells are not the scene's Q1 elements, each
//! refusal naming what is off: a triangle or tetrahedron mesh on the scene's nodes (each
//! element split; DOLFINx's default mesh of the bar is such a mesh) by its element's name, a
//! cell type the harness does not interpolate (a pixel, a quadratic quadrilateral) by its VTK
//! type and the allowed ones, a quadrilateral listed out of VTK's order by its points, and an
//! XDMF file whose `TopologyType` is `Triangle` by that type. The harness's own cells and those
//! DOLFINx and GetFEM write verify as before (`verify_box`, `real_codes`).

use std::path::{Path, PathBuf};

use crate::common::expect_error;
use crate::verify_box::{run_every_step, s, scene_at_levels, scratch, write_collection};
use signorini::harness::external::mesh::{Cells, Topology};
use signorini::harness::external::nodal_snapshot::NodalSnapshot;
use signorini::harness::external::pvd::{read_collection, read_snapshot};

/// `snapshot` written to `path` as an ASCII `.vtu` with the cells `cells`.
fn write_vtu(path: &Path, snapshot: &NodalSnapshot, cells: &Cells) {
    let join = |v: &mut dyn Iterator<Item = String>| v.collect::<Vec<_>>().join(" ");
    let mut point_data = String::new();
    for a in &snapshot.arrays {
        point_data += &format!(
            "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" \
             format=\"ascii\">{}</DataArray>\n",
            a.name,
            a.components,
            join(&mut a.values.iter().map(|x| format!("{x:?}")))
        );
    }
    let xml = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\">\n\
         <UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<PointData>\n\
         {point_data}</PointData>\n<Points>\n<DataArray type=\"Float64\" \
         NumberOfComponents=\"3\" format=\"ascii\">{}</DataArray>\n</Points>\n<Cells>\n\
         <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">{}</DataArray>\n\
         <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">{}</DataArray>\n\
         <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">{}</DataArray>\n</Cells>\n\
         </Piece>\n</UnstructuredGrid>\n</VTKFile>\n",
        snapshot.points.len(),
        cells.len(),
        join(&mut snapshot.points.iter().flatten().map(|x| format!("{x:?}"))),
        join(&mut cells.connectivity.iter().map(usize::to_string)),
        join(&mut cells.offsets.iter().map(usize::to_string)),
        join(&mut cells.types.iter().map(u8::to_string)),
    );
    std::fs::write(path, xml).unwrap();
}

/// The collection `pvd` rewritten into `dir`, each snapshot's cells replaced by `recell` of
/// them: the new collection.
fn recelled(pvd: &Path, dir: &Path, recell: &dyn Fn(&Cells) -> Cells) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let mut datasets = Vec::new();
    for (k, entry) in read_collection(pvd).unwrap().iter().enumerate() {
        let snapshot = read_snapshot(&entry.file).unwrap();
        let Some(Topology::Cells(cells)) = &snapshot.topology else {
            panic!("the harness writes its cells")
        };
        let file = format!("snapshot-{k}.vtu");
        write_vtu(&dir.join(&file), &snapshot, &recell(cells));
        datasets.push((entry.time, file));
    }
    write_collection(&dir.join("fields.pvd"), &datasets)
}

/// Each cell of `cells` replaced by the cells `split` makes of its points.
fn each_cell(cells: &Cells, split: &dyn Fn(&[usize]) -> Vec<(u8, Vec<usize>)>) -> Cells {
    let mut out = Cells::default();
    for (_, points) in cells.iter() {
        for (vtk, nodes) in split(points) {
            out.push(vtk, &nodes);
        }
    }
    out
}

/// A quadrilateral `q` (VTK order) cut along its diagonal 0–2 into two triangles of type `vtk`.
fn two_triangles(q: &[usize], vtk: u8) -> Vec<(u8, Vec<usize>)> {
    vec![(vtk, vec![q[0], q[1], q[2]]), (vtk, vec![q[0], q[2], q[3]])]
}

/// A hexahedron `h` (VTK order) cut into six tetrahedra around its diagonal 0–6.
fn six_tetrahedra(h: &[usize]) -> Vec<(u8, Vec<usize>)> {
    [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]]
        .iter()
        .map(|&[a, b]| (10, vec![h[0], h[a], h[b], h[6]]))
        .collect()
}

/// `verify` of `file` against `scene` (arrays named, no reference needed: every file is read
/// and checked first).
fn verify_args<'a>(scene: &'a Path, file: &'a Path, cache: &'a Path) -> Vec<&'a str> {
    vec![
        "verify",
        s(scene),
        s(file),
        "--code",
        "recelled",
        "--code-version",
        "1",
        "--velocity",
        "velocity",
        "--multiplier",
        "contact_multiplier",
        "--cache",
        s(cache),
    ]
}

#[test]
fn a_simplex_mesh_on_the_scenes_nodes_is_refused_by_name_not_read_as_q1() {
    let dir = scratch("mesh-simplex");
    for (scene_file, nx) in [("scenes/bar2d.json", 5), ("scenes/bar3d.json", 5)] {
        let scene = scene_at_levels(&dir, scene_file, &[nx]);
        let cache = dir.join("references");
        let three = scene_file.contains("3d");
        let pvd = run_every_step(&scene, nx, &dir.join(format!("run-{three}")));
        let splits: Vec<(&dyn Fn(&[usize]) -> Vec<(u8, Vec<usize>)>, &str, &str)> = if three {
            vec![(
                &six_tetrahedra,
                "a tetrahedron (VTK cell type 10)",
                "tetrahedra",
            )]
        } else {
            vec![
                (
                    &|q| two_triangles(q, 5),
                    "a triangle (VTK cell type 5)",
                    "triangles",
                ),
                (
                    &|q| two_triangles(q, 69),
                    "a triangle (VTK cell type 69)",
                    "triangles",
                ),
            ]
        };
        for (k, (split, named, plural)) in splits.into_iter().enumerate() {
            let split_dir = dir.join(format!("split-{three}-{k}"));
            let file = recelled(&pvd, &split_dir, &|cells| each_cell(cells, split));
            expect_error(
                &verify_args(&scene, &file, &cache),
                2,
                &[
                    "snapshot-0.vtu",
                    "cell 0",
                    named,
                    &format!("a mesh of {plural} is not verified"),
                ],
            );
        }
    }
}

#[test]
fn a_cell_the_harness_does_not_interpolate_or_out_of_order_is_refused_naming_it() {
    let dir = scratch("mesh-types");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[5]);
    let cache = dir.join("references");
    let pvd = run_every_step(&scene, 5, &dir.join("run"));
    // A pixel (VTK 8: its points in lexicographic order, not a quadrilateral's cycle) and a
    // quadratic quadrilateral (VTK 23, its mid-edge nodes left out): types the harness does not
    // interpolate, refused with the allowed ones.
    let pixel = recelled(&pvd, &dir.join("pixel"), &|cells| {
        each_cell(cells, &|q| vec![(8, vec![q[0], q[1], q[3], q[2]])])
    });
    expect_error(
        &verify_args(&scene, &pixel, &cache),
        2,
        &[
            "Cells types",
            "cell 0",
            "VTK cell type 8 of 4 points",
            "quadrilaterals (VTK 9",
        ],
    );
    let quadratic = recelled(&pvd, &dir.join("quadratic"), &|cells| {
        each_cell(cells, &|q| vec![(23, q.to_vec())])
    });
    expect_error(
        &verify_args(&scene, &quadratic, &cache),
        2,
        &["VTK cell type 23 of 4 points", "hexahedra (VTK 12"],
    );
    // A Lagrange quadrilateral of the linear cell's points is read as the quadrilateral; one of
    // 9 points (order 2) is not.
    let lagrange = recelled(&pvd, &dir.join("lagrange9"), &|cells| {
        each_cell(cells, &|q| vec![(70, [q, &q[..4], &q[..1]].concat())])
    });
    expect_error(
        &verify_args(&scene, &lagrange, &cache),
        2,
        &["VTK cell type 70 of 9 points"],
    );
    // The first quadrilateral with its last two points swapped: a bow tie, not an element.
    let twisted = recelled(&pvd, &dir.join("twisted"), &|cells| {
        let mut out = Cells::default();
        for (k, (vtk, q)) in cells.iter().enumerate() {
            let q = if k == 0 {
                vec![q[0], q[1], q[3], q[2]]
            } else {
                q.to_vec()
            };
            out.push(vtk, &q);
        }
        out
    });
    expect_error(
        &verify_args(&scene, &twisted, &cache),
        2,
        &[
            "Cells connectivity",
            "cell 0",
            "its vertices in VTK's order",
        ],
    );
    // The first cell twice and the last (cell 4 of the five) left out.
    let missing = recelled(&pvd, &dir.join("missing"), &|cells| {
        let mut out = Cells::default();
        for k in 0..cells.len() {
            let from = if k + 1 == cells.len() { 0 } else { k };
            out.push(cells.types[from], cells.cell(from));
        }
        out
    });
    expect_error(
        &verify_args(&scene, &missing, &cache),
        2,
        &["Cells connectivity", "cell 4", "each once"],
    );
}

#[test]
fn an_xdmf_mesh_of_triangles_is_refused_by_its_topology_type() {
    let dir = scratch("mesh-xdmf");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10]);
    let cache = dir.join("references");
    let stem = "dolfinx-bar2d-crank-nicolson-standard-level10";
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/external/dolfinx-xdmf");
    std::fs::copy(
        source.join(format!("{stem}.h5")),
        dir.join(format!("{stem}.h5")),
    )
    .unwrap();
    let text = std::fs::read_to_string(source.join(format!("{stem}.xdmf"))).unwrap();
    for (topology, needles) in [
        (
            "Triangle",
            [
                "TopologyType \"Triangle\"",
                "a mesh of triangles is not verified",
            ],
        ),
        (
            "Polygon",
            ["Topology.TopologyType", "Tetrahedron, Hexahedron"],
        ),
    ] {
        let edited = text.replace(
            "TopologyType=\"Quadrilateral\"",
            &format!("TopologyType=\"{topology}\""),
        );
        assert_ne!(edited, text, "the fixture declares quadrilaterals");
        let xdmf = dir.join(format!("{stem}.xdmf"));
        std::fs::write(&xdmf, edited).unwrap();
        expect_error(&verify_args(&scene, &xdmf, &cache), 2, &needles);
    }
}
