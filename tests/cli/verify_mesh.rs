//! `signorini verify` reads a box run's cells (issue 57). The harness's own 2D and 3D runs,
//! their cells rewritten here: a cell type the harness does not interpolate (a pixel, a quadratic
//! quadrilateral) is refused by its VTK type and the allowed ones, a quadrilateral listed out of
//! VTK's order by its points; likewise an XDMF file's topology (its connectivity read), and one of
//! another type by that type. The harness's own cells and those DOLFINx and GetFEM write verify
//! as before (`verify_box`, `real_codes`).
//!
//! A series on its own mesh (each element split into triangles or Kuhn tetrahedra on the same
//! nodes, a P1 field; an XDMF triangle topology) verifies end to end against the reference's
//! projection on the finest study level, with its mesh, `h`, `Δt` and bound said, and its
//! contact quantities (the resultant over the face, the face centre's pressure and
//! displacement) beside the reference's; the Q1 runs
//! forced through that path (`--own-mesh`) give the structured path's errors to round-off; a
//! mesh with a hole, or a sample off the finest level's time grid, is refused naming it.
//!
//! The distance between a field on its own mesh and a reference on the scene's structured mesh
//! ([`pair_errors`]): on the scene's coarser structured mesh it is the structured path's `eᵀMe`,
//! `eᵀSe` to round-off; on the bars' meshes split into triangles and tetrahedra, with a
//! multilinear field, the exact errors within the quadrature's stated bound; a mesh that leaves a
//! hole or spans another box is refused naming what is off.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common::{expect_error, signorini, success_stdout};
use crate::verify_box::{
    errors, read_json, run_every_step, s, scene_at_levels, scratch, write_collection,
};
use signorini::engine::fem::{BoxMesh, Elasticity, Prolongation};
use signorini::harness::external::mesh::{
    check_domain, gauss_legendre, pair_errors, Cell, CellKind, Cells, ElementMesh, Quadrature,
    Topology,
};
use signorini::harness::external::nodal_snapshot::NodalSnapshot;
use signorini::harness::external::pvd::{read_collection, read_snapshot};
use signorini::harness::external::verify::own_mesh::QUADRATURE;
use signorini::harness::external::xdmf::XdmfSeries;
use signorini::harness::run::nested_comparison::norm_matrices::NormMatrices;

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

/// The cells (VTK type and points) one cell's points are cut into.
type Split<'a> = &'a dyn Fn(&[usize]) -> Vec<(u8, Vec<usize>)>;

/// Each cell of `cells` replaced by the cells `split` makes of its points.
fn each_cell(cells: &Cells, split: Split<'_>) -> Cells {
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

/// `verify` of the series `files` against `scene` with `extra` arguments (the multipliers'
/// array among them, when it is read), writing verify.json
/// into `out`: its JSON and what it printed.
fn verify_series(
    scene: &Path,
    files: &[PathBuf],
    cache: &Path,
    out: &Path,
    extra: &[&str],
) -> (Value, String) {
    let mut args = vec!["verify", s(scene)];
    args.extend(files.iter().map(|f| s(f)));
    args.extend([
        "--code",
        "signorini",
        "--code-version",
        "test",
        "--label",
        "cn-std",
        "--velocity",
        "velocity",
        "--cache",
        s(cache),
        "--out",
        s(out),
    ]);
    args.extend(extra);
    let printed = success_stdout(&signorini(&args));
    (read_json(&out.join("verify.json")), printed)
}

/// The displacement norms' errors of the first series of a verify.json.
fn displacement_errors(verified: &Value) -> Vec<(String, Vec<f64>)> {
    errors(&verified["series"][0]["rates"])
        .into_iter()
        .filter(|(norm, _)| norm.starts_with("u_"))
        .collect()
}

/// The harness's Crank–Nicolson/standard runs of the bar `scene_file` (2D or 3D) at levels 5
/// and 10 (the scene's study levels, the reference on 40), each as its own `.pvd` and with its
/// cells split into triangles (two per element) or Kuhn tetrahedra (six): the scene, the
/// reference cache, the Q1 series and the simplex series.
fn bar_series(dir: &Path, scene_file: &str) -> (PathBuf, PathBuf, Vec<PathBuf>, Vec<PathBuf>) {
    std::fs::create_dir_all(dir).unwrap();
    let scene = scene_at_levels(dir, scene_file, &[5, 10]);
    let three = scene_file.contains("3d");
    let q1: Vec<PathBuf> = [5, 10]
        .iter()
        .map(|&nx| run_every_step(&scene, nx, &dir.join(format!("run{nx}"))))
        .collect();
    let triangles = |q: &[usize]| two_triangles(q, 5);
    let split: Split<'_> = if three { &six_tetrahedra } else { &triangles };
    let simplex = q1
        .iter()
        .enumerate()
        .map(|(k, pvd)| {
            recelled(pvd, &dir.join(format!("split{k}")), &|c| {
                each_cell(c, split)
            })
        })
        .collect();
    (scene, dir.join("references"), q1, simplex)
}

/// A triangle series of the 2D bar and a tetrahedral series of the 3D bar (the harness's own
/// runs at levels 5 and 10, every element split, the same nodal values: a P1 field on the
/// nodes of the Q1 one) verify end to end against the reference's projection on level 10: exit
/// 0, the mesh, h and the bound said in verify.json and printed, the displacement norms
/// measured; the energy on the scene's cells through the own-mesh path the structured path's to
/// round-off; the resultant contact force's `lambda_L2` and oscillation indicator those of the
/// structured path to round-off; the rates' bias widened by the stated bound and the findings'
/// caveats said; the face
/// centre's displacement, resultant and pressure recorded at every sample, and `lambda_L2` not
/// computed without `--multiplier`, saying so; the same Q1 runs
/// forced through the own-mesh path give the structured path's errors to round-off, and the
/// simplex series' errors differ from the Q1 series' by no more than their stated bound and the
/// fields' own distance (each P1 field against its Q1 field, by the same quadrature).
#[test]
fn a_simplex_series_of_the_bars_verifies_end_to_end_against_the_finest_projection() {
    let dir = scratch("mesh-own");
    for (scene_file, kind, cells) in [
        ("scenes/bar2d.json", "triangles", [10, 20]),
        ("scenes/bar3d.json", "tetrahedra", [30, 60]),
    ] {
        let sub = dir.join(kind);
        let (scene, cache, q1, simplex) = bar_series(&sub, scene_file);
        let declared = [
            "--multiplier",
            "contact_multiplier",
            "--scheme",
            "crank-nicolson",
            "--mass",
            "standard",
        ];
        let (structured, _) = verify_series(&scene, &q1, &cache, &sub.join("q1"), &declared);
        let forced_args = [
            "--own-mesh",
            "--multiplier",
            "contact_multiplier",
            "--mass",
            "standard",
        ];
        let (forced, _) = verify_series(&scene, &q1, &cache, &sub.join("forced"), &forced_args);
        let (own, printed) = verify_series(&scene, &simplex, &cache, &sub.join("own"), &declared);
        // The findings on the own-mesh series are widened by its stated bound, and say so.
        let bias = |v: &Value| v["rate_bias"]["u_Linf_V"].as_f64();
        let (widened, reference_only) = (bias(&own), bias(&structured).unwrap());
        assert!(
            widened.is_none_or(|b| b > reference_only),
            "{kind}: {widened:?} against {reference_only}"
        );
        let caveats = own["caveats"].as_array().unwrap();
        assert!(caveats[0]
            .as_str()
            .unwrap()
            .starts_with("On their own mesh: `cn-std`"));
        assert!(structured.get("caveats").is_none());
        assert!(printed.contains("What these findings rest on"), "{printed}");
        let expected = displacement_errors(&structured);
        assert_eq!(expected.len(), 4);
        for ((norm, e), (forced_norm, f)) in expected.iter().zip(displacement_errors(&forced)) {
            assert_eq!(norm, &forced_norm);
            for (a, b) in e.iter().zip(&f) {
                assert!(
                    (a - b).abs() <= 1e-12 * a.abs(),
                    "{kind} {norm}: {a} forced {b}"
                );
            }
        }
        let series = &own["series"][0];
        let runs = series["runs"].as_array().unwrap();
        for (k, run) in runs.iter().enumerate() {
            let record = &run["own_mesh"];
            assert_eq!(record["mesh"], format!("own mesh: {} {kind}", cells[k]));
            assert!(record["longest_edge"].as_f64().unwrap() > 0.0);
            assert!(printed.contains(&format!("own mesh: {} {kind}", cells[k])));
            let h = record["longest_edge"].as_f64().unwrap();
            assert_eq!(series["levels"][k]["h"].as_f64(), Some(h));
            assert!(
                printed.contains(&format!("h (longest edge) {h:.4e}")),
                "{printed}"
            );
        }
        assert!(printed.contains("projections on the finest study level 10"));
        // The resultant over the contact face is the structured path's total force: the same
        // lambda_L2 and oscillation indicator, on the split cells as on the scene's; the energy
        // on the scene's cells through the own-mesh path is the structured path's.
        let norm_errors = |verified: &Value, key: &str| -> Vec<f64> {
            let all = errors(&verified["series"][0]["rates"]);
            all.into_iter().find(|(n, _)| n == key).unwrap().1
        };
        let indicator = |verified: &Value, k: usize| {
            verified["series"][0]["levels"][k]["multiplier_variation_ratio"]
                .as_f64()
                .unwrap()
        };
        for (key, other) in [
            ("lambda_L2", &own),
            ("energy_Linf", &forced),
            ("energy_L2", &forced),
        ] {
            let expected = norm_errors(&structured, key);
            for (a, b) in expected.iter().zip(norm_errors(other, key)) {
                assert!((a - b).abs() <= 1e-12 * a.abs(), "{kind} {key} {a} own {b}");
            }
            assert!(norm_errors(&own, key)
                .iter()
                .all(|e| e.is_finite() && *e > 0.0));
        }
        for (k, run) in runs.iter().enumerate() {
            let (a, b) = (indicator(&structured, k), indicator(&own, k));
            assert!((a - b).abs() <= 1e-12 * a, "{kind} indicator {a} own {b}");
            let contact = &run["own_mesh"]["contact"];
            let samples = contact["time"].as_array().unwrap().len();
            assert_eq!(Some(samples as u64), run["samples"].as_u64());
            for q in ["displacement", "force", "pressure"] {
                assert_eq!(contact[q].as_array().unwrap().len(), samples, "{q}");
                let linf = contact["errors"][format!("{q}_Linf")].as_f64().unwrap();
                let scale = contact["errors"][format!("{q}_scale")].as_f64().unwrap();
                assert!(linf > 0.0 && scale > 0.0 && linf.is_finite(), "{kind} {q}");
            }
        }
        assert!(printed.contains("at the face centre"), "{printed}");
        let (without, _) = verify_series(&scene, &simplex, &cache, &sub.join("without"), &[]);
        let reason = without["series"][0]["not_computed"]
            .as_array()
            .unwrap()
            .iter()
            .find(|n| n["norm"] == "lambda_L2")
            .map(|n| n["reason"].as_str().unwrap().to_string());
        assert!(
            reason
                .as_deref()
                .is_some_and(|r| r.contains("--multiplier NAME")),
            "{reason:?}"
        );
        let measured = displacement_errors(&own);
        assert_eq!(measured.len(), 4);
        for ((norm, q), (_, p)) in expected.iter().zip(&measured) {
            for k in 0..2 {
                let record = &runs[k]["own_mesh"];
                let bound = record["bound"][norm].as_f64().unwrap();
                let quadrature = record["quadrature_error"][norm].as_f64().unwrap();
                let d = if kind == "triangles" { 2 } else { 3 };
                let apart = field_distance(&pair::bar(d, 5 << k), &simplex[k], &q1[k], norm);
                eprintln!(
                    "{kind} {norm} level {k}: Q1 {:.6e} own {:.6e} bound {bound:.3e} \
                     (quadrature {quadrature:.3e}) fields apart {apart:.3e}",
                    q[k], p[k]
                );
                assert!(
                    bound > quadrature && bound < p[k],
                    "{kind} {norm}: bound {bound}"
                );
                // Both errors are (p² + r)^½ with one r: they differ by at most the fields'
                // distance and the quadrature's error.
                assert!(
                    (p[k] - q[k]).abs() <= quadrature + apart,
                    "{kind} {norm}: {} against {} beyond {quadrature} + {apart}",
                    p[k],
                    q[k]
                );
            }
        }
    }
}

/// The time norm `norm` (`u_Linf_H`, …) of the distance between the Q1 field of the series
/// `q1` on `mesh` (the scene's at its level) and the field of the same nodal values on the
/// cells of `own`, sample by sample in `H` or `V` by [`pair_errors`] with the own-mesh rule.
fn field_distance(mesh: &BoxMesh, own: &Path, q1: &Path, norm: &str) -> f64 {
    let d = mesh.dim();
    let own_entries = read_collection(own).unwrap();
    let mut by_time = Vec::new();
    for (entry, own_entry) in read_collection(q1).unwrap().iter().zip(&own_entries) {
        let snapshot = read_snapshot(&entry.file).unwrap();
        let own_snapshot = read_snapshot(&own_entry.file).unwrap();
        let Some(Topology::Cells(cells)) = &own_snapshot.topology else {
            panic!("cells")
        };
        let external = ElementMesh::of_cells(d, own_snapshot.points.clone(), cells).unwrap();
        let values = |s: &NodalSnapshot| -> Vec<f64> {
            let a = s.array("displacement").unwrap();
            (0..s.points.len())
                .flat_map(|k| a.row(k)[..d].to_vec())
                .collect()
        };
        // The Q1 field in the box mesh's node order: each node's point found in the file.
        let u = values(&snapshot);
        let mut nodal = vec![0.0; mesh.n_nodes() * d];
        for node in 0..mesh.n_nodes() {
            let x = mesh.node(node);
            let k = snapshot
                .points
                .iter()
                .position(|p| (0..d).all(|c| (p[c] - x[c]).abs() < 1e-12))
                .unwrap();
            nodal[node * d..(node + 1) * d].copy_from_slice(&u[k * d..(k + 1) * d]);
        }
        let e = pair_errors(
            &external,
            &values(&own_snapshot),
            mesh,
            &nodal,
            &Elasticity::NOTE,
            QUADRATURE,
        )
        .unwrap();
        by_time.push((entry.time, if norm.ends_with('H') { e.h() } else { e.v() }));
    }
    let linf = by_time.iter().fold(0.0f64, |m, &(_, e)| m.max(e));
    let l2 = by_time
        .windows(2)
        .map(|w| 0.5 * (w[1].0 - w[0].0) * (w[0].1 * w[0].1 + w[1].1 * w[1].1))
        .sum::<f64>()
        .sqrt();
    if norm.contains("Linf") {
        linf
    } else {
        l2
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
fn an_xdmf_topology_is_read_and_refused_where_its_cells_are_not_the_scenes() {
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
    // The fixture's quadrilaterals, as the reader reads them from its HDF5 topology.
    let series = XdmfSeries::read(&source.join(format!("{stem}.xdmf"))).unwrap();
    let Some(Topology::Cells(quads)) = series.snapshot(0).unwrap().topology else {
        panic!("the fixture's topology is read")
    };
    assert_eq!((quads.len(), quads.types[0]), (10, 9));
    let (start, end) = (
        text.find("<Topology").unwrap(),
        text.find("</Topology>").unwrap() + "</Topology>".len(),
    );
    // The fixture's topology replaced by an inline one of `kind` with `cells`.
    let inline = |kind: &str, cells: &Cells| {
        let n = cells.cell(0).len();
        let rows: Vec<String> = cells.connectivity.iter().map(usize::to_string).collect();
        format!(
            "{}<Topology TopologyType=\"{kind}\" NumberOfElements=\"{}\"><DataItem \
             Dimensions=\"{} {n}\" NumberType=\"Int\" Format=\"XML\">{}</DataItem></Topology>{}",
            &text[..start],
            cells.len(),
            cells.len(),
            rows.join(" "),
            &text[end..]
        )
    };
    let triangles = each_cell(&quads, &|q| two_triangles(q, 5));
    let mut twisted = Cells::default();
    for (k, (vtk, q)) in quads.iter().enumerate() {
        let q = if k == 3 {
            vec![q[0], q[1], q[3], q[2]]
        } else {
            q.to_vec()
        };
        twisted.push(vtk, &q);
    }
    let polygon = text.replace("TopologyType=\"Quadrilateral\"", "TopologyType=\"Polygon\"");
    assert_ne!(polygon, text, "the fixture declares quadrilaterals");
    // Triangles are a mesh of the code's own, measured on its cells.
    let xdmf = dir.join(format!("{stem}.xdmf"));
    std::fs::write(&xdmf, inline("Triangle", &triangles)).unwrap();
    let printed = success_stdout(&signorini(&verify_args(&scene, &xdmf, &cache)));
    assert!(printed.contains("own mesh: 20 triangles"), "{printed}");
    for (edited, needles) in [
        (
            inline("Quadrilateral", &twisted),
            ["Cells connectivity", "cell 3"],
        ),
        (
            polygon,
            [
                "Topology.TopologyType = \"Polygon\"",
                "Tetrahedron, Hexahedron",
            ],
        ),
    ] {
        let xdmf = dir.join(format!("{stem}.xdmf"));
        std::fs::write(&xdmf, edited).unwrap();
        expect_error(&verify_args(&scene, &xdmf, &cache), 2, &needles);
    }
}

/// A series on its own mesh is refused before any reference is sought when its triangles do
/// not cover the box (the last one left out: a hole, named by the measures), when a sample's
/// time is not a step of the finest study level (named by its sample), or when its samples stop
/// before `T`.
#[test]
fn an_own_mesh_off_the_box_or_off_the_finest_time_grid_is_refused_naming_it() {
    let dir = scratch("mesh-own-refused");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[5]);
    let cache = dir.join("references");
    let pvd = run_every_step(&scene, 5, &dir.join("run"));
    let holed = recelled(&pvd, &dir.join("holed"), &|cells| {
        let all = each_cell(cells, &|q| two_triangles(q, 5));
        let mut out = Cells::default();
        for k in 0..all.len() - 1 {
            out.push(all.types[k], all.cell(k));
        }
        out
    });
    expect_error(
        &verify_args(&scene, &holed, &cache),
        2,
        &[
            "snapshot-0.vtu",
            "Cells",
            "leave a hole or overlap",
            "a conforming mesh",
        ],
    );
    let triangles = recelled(&pvd, &dir.join("triangles"), &|cells| {
        each_cell(cells, &|q| two_triangles(q, 5))
    });
    let entries = read_collection(&triangles).unwrap();
    let dt = entries[1].time - entries[0].time;
    let shifted: Vec<(f64, String)> = entries
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let t = if k == 2 { e.time + dt / 3.0 } else { e.time };
            (
                t,
                e.file.file_name().unwrap().to_string_lossy().into_owned(),
            )
        })
        .collect();
    let off_grid = write_collection(&dir.join("triangles").join("shifted.pvd"), &shifted);
    let short = write_collection(&dir.join("triangles").join("short.pvd"), &shifted[..2]);
    expect_error(
        &verify_args(&scene, &short, &cache),
        2,
        &["short.pvd", "timestep", "samples from 0 to T = 2"],
    );
    expect_error(
        &verify_args(&scene, &off_grid, &cache),
        2,
        &[
            "shifted.pvd",
            "timestep",
            "sample 2",
            "finest study level 5",
        ],
    );
}

// The pair tests index components and axes as the formulas write them.
#[allow(clippy::needless_range_loop)]
mod pair {
    use super::*;

    /// The fields of the pair tests: `d` components per node of `points`, from `f`.
    fn nodal(points: &[[f64; 3]], d: usize, f: &dyn Fn([f64; 3]) -> [f64; 3]) -> Vec<f64> {
        points.iter().flat_map(|&p| f(p)[..d].to_vec()).collect()
    }

    /// A smooth field no finite element space reproduces, 0 on the clamped face `x_d = 1` (as the
    /// harness's unknowns are): its components differ.
    fn smooth(d: usize, shift: f64) -> impl Fn([f64; 3]) -> [f64; 3] {
        move |x: [f64; 3]| {
            let clamp = 1.0 - x[d - 1];
            let mut u = [0.0; 3];
            for (c, u) in u.iter_mut().enumerate().take(d) {
                *u = clamp * (3.0 * x[0] + 2.0 * x[1] + x[2] + c as f64 + shift).sin();
            }
            u
        }
    }

    /// The bar's box at the level `n` along the axis (`n / 5` rounded up across, as the scenes).
    pub(super) fn bar(d: usize, n: usize) -> BoxMesh {
        let across = n.div_ceil(10).max(1);
        if d == 2 {
            BoxMesh::new(&[0.1, 1.0], &[across, n]).unwrap()
        } else {
            BoxMesh::new(&[0.1, 0.1, 1.0], &[across, across, n]).unwrap()
        }
    }

    /// The nodal values `nodal` of `mesh` on its unknowns (the clamped nodes' left out).
    fn unknowns(mesh: &BoxMesh, nodal: &[f64]) -> Vec<f64> {
        let d = mesh.dim();
        let mut u = vec![0.0; mesh.n_dofs()];
        for node in 0..mesh.n_nodes() {
            for c in 0..d {
                if let Some(dof) = mesh.dof_of(node, c) {
                    u[dof] = nodal[node * d + c];
                }
            }
        }
        u
    }

    #[test]
    fn the_pair_quadrature_on_the_scenes_nested_mesh_is_the_structured_path_to_round_off() {
        for d in [2, 3] {
            let (coarse, fine) = (bar(d, 5), bar(d, 20));
            let u_h = nodal(&coarse.nodes().collect::<Vec<_>>(), d, &smooth(d, 0.0));
            let u_ref = nodal(&fine.nodes().collect::<Vec<_>>(), d, &smooth(d, 0.3));
            // Today's path: the coarse field prolongated exactly, e = P U − u in the fine M and S.
            let prolongation = Prolongation::new(&coarse, &fine).unwrap();
            let mut e = vec![0.0; fine.n_dofs()];
            prolongation.apply_into(
                &unknowns(&coarse, &u_h)[prolongation.coarse_range()],
                &mut e,
            );
            for (e, u) in e.iter_mut().zip(unknowns(&fine, &u_ref)) {
                *e -= u;
            }
            let matrices = NormMatrices::of(&fine, &Elasticity::NOTE);
            let (h2, v2) = matrices.squared(&e, &mut vec![0.0; e.len()]);
            let external = ElementMesh::of_box(&coarse);
            for quadrature in [
                Quadrature {
                    gauss: 2,
                    subcells: 1,
                },
                Quadrature::DEFAULT,
                Quadrature {
                    gauss: 2,
                    subcells: 3,
                },
            ] {
                let pair = pair_errors(
                    &external,
                    &u_h,
                    &fine,
                    &u_ref,
                    &Elasticity::NOTE,
                    quadrature,
                )
                .unwrap();
                let (dh, dv) = ((pair.h() - h2.sqrt()).abs(), (pair.v() - v2.sqrt()).abs());
                eprintln!(
                    "{d}D nested, {quadrature:?}: H {:.15e} against {:.15e} ({dh:.1e}), V {:.15e} \
                 against {:.15e} ({dv:.1e})",
                    pair.h(),
                    h2.sqrt(),
                    pair.v(),
                    v2.sqrt()
                );
                assert!(dh <= 1e-12 * h2.sqrt(), "{d}D {quadrature:?}: H {dh:e}");
                assert!(dv <= 1e-12 * v2.sqrt(), "{d}D {quadrature:?}: V {dv:e}");
            }
        }
    }

    /// The Gauss–Legendre rule of `n` points on `[0, 1]`.
    fn unit_gauss(n: usize) -> Vec<(f64, f64)> {
        let (x, w) = gauss_legendre(n);
        x.iter()
            .zip(&w)
            .map(|(x, w)| (0.5 * (x + 1.0), 0.5 * w))
            .collect()
    }

    /// `∫ |e|²` and `∫ |∇e|²` of `e = I f − f` over the simplex mesh `mesh` (`I f` its P1
    /// interpolant, `nodal`), exactly for a polynomial `f` (its gradient `grad`) of degree at most 3:
    /// on each simplex by the collapsed (Duffy) tensor rule of 5 Gauss points per axis, exact for
    /// the integrands' degree (at most 6, 8 in the collapsed coordinate).
    fn simplex_errors(
        mesh: &ElementMesh,
        nodal: &[f64],
        f: &dyn Fn([f64; 3]) -> [f64; 3],
        grad: &dyn Fn([f64; 3]) -> [[f64; 3]; 3],
    ) -> (f64, f64) {
        let d = mesh.dim();
        let rule = unit_gauss(5);
        let (mut l2, mut h1) = (0.0, 0.0);
        for (k, cell) in mesh.cells().iter().enumerate() {
            let volume = mesh.measure(k).abs();
            let factorial = if d == 2 { 2.0 } else { 6.0 };
            let p = |a: usize| mesh.points()[cell.vertices[a]];
            let third = if d == 2 {
                vec![(0.0, 1.0)]
            } else {
                rule.clone()
            };
            for &(s, ws) in &rule {
                for &(t, wt) in &rule {
                    for &(r, wr) in &third {
                        // λ₁ = s, λ₂ = t(1 − s), λ₃ = r(1 − s)(1 − t): the unit simplex.
                        let lambda = [s, t * (1.0 - s), r * (1.0 - s) * (1.0 - t)];
                        let jacobian = if d == 2 {
                            1.0 - s
                        } else {
                            (1.0 - s).powi(2) * (1.0 - t)
                        };
                        let w = ws * wt * wr * jacobian * volume * factorial;
                        let mut x = p(0);
                        for a in 1..=d {
                            for c in 0..d {
                                x[c] += lambda[a - 1] * (p(a)[c] - p(0)[c]);
                            }
                        }
                        let at = mesh.evaluate_in(k, lambda, nodal);
                        let (exact, exact_grad) = (f(x), grad(x));
                        for c in 0..d {
                            l2 += w * (at.value[c] - exact[c]).powi(2);
                            for j in 0..d {
                                h1 += w * (at.gradient[c][j] - exact_grad[c][j]).powi(2);
                            }
                        }
                    }
                }
            }
        }
        (l2, h1)
    }

    /// The level-`n` bar's mesh with each element split into simplices: two triangles along the
    /// diagonal 0–2 in 2D, six tetrahedra around the diagonal 0–6 in 3D (Kuhn's, conforming).
    fn split_bar(d: usize, n: usize) -> ElementMesh {
        let mesh = bar(d, n);
        let mut cells = Vec::new();
        for nodes in mesh.elements() {
            let split = if d == 2 {
                two_triangles(&nodes, 5)
            } else {
                six_tetrahedra(&nodes)
            };
            for (vtk, vertices) in split {
                let kind = CellKind::of_vtk(vtk, vertices.len()).unwrap();
                cells.push(Cell { kind, vertices });
            }
        }
        ElementMesh::new(d, mesh.nodes().collect(), cells).unwrap()
    }

    /// The multilinear `f` of the simplex tests and its gradient (`scripts/mesh_fixtures.py`'s).
    fn multilinear(d: usize) -> (Field, Gradient) {
        let f = move |x: [f64; 3]| {
            let m: f64 = x[..d].iter().product();
            [
                m,
                2.0 * m + x[0],
                if d == 3 { m - x[1] * x[0] } else { 0.0 },
            ]
        };
        let grad = move |x: [f64; 3]| {
            let partial = |j: usize| -> f64 { (0..d).filter(|&i| i != j).map(|i| x[i]).product() };
            let mut g = [[0.0; 3]; 3];
            for j in 0..d {
                g[0][j] = partial(j);
                g[1][j] = 2.0 * partial(j) + if j == 0 { 1.0 } else { 0.0 };
                if d == 3 {
                    g[2][j] = partial(j) - [x[1], x[0], 0.0][j];
                }
            }
            g
        };
        (Box::new(f), Box::new(grad))
    }

    /// A field and its gradient in closed form.
    type Field = Box<dyn Fn([f64; 3]) -> [f64; 3]>;
    type Gradient = Box<dyn Fn([f64; 3]) -> [[f64; 3]; 3]>;

    /// The P1 field `u_h` on the simplex mesh `external` (`what`, for the messages), the
    /// interpolant of [`multilinear`]: its pair errors against the level-20 bar's Q1 reference
    /// of `f` (which is `f`) are within the stated bound of the exact ones, with 3 Gauss points
    /// per axis on 1, 2, 4 and 8 subcells; the relative error of the first rule, largest of L²
    /// and the H¹ seminorm.
    fn within_bound(external: &ElementMesh, u_h: &[f64], what: &str) -> f64 {
        let d = external.dim();
        let (f, grad) = multilinear(d);
        let fine = bar(d, 20);
        let u_ref = nodal(&fine.nodes().collect::<Vec<_>>(), d, &f);
        let (l2, h1) = simplex_errors(external, u_h, &f, &grad);
        let exact = [l2.sqrt(), h1.sqrt()];
        let rules: Vec<[f64; 2]> = [1, 2, 4, 8]
            .iter()
            .map(|&subcells| {
                let quadrature = Quadrature { gauss: 3, subcells };
                let pair = pair_errors(external, u_h, &fine, &u_ref, &Elasticity::NOTE, quadrature)
                    .unwrap();
                let got = [pair.l2_squared.sqrt(), pair.h1_seminorm_squared.sqrt()];
                eprintln!(
                    "{what}, {quadrature:?}: L2 {:.6e} (exact {:.6e}, relative {:.1e}), H1 \
                     seminorm {:.6e} (exact {:.6e}, relative {:.1e})",
                    got[0],
                    exact[0],
                    (got[0] - exact[0]).abs() / exact[0],
                    got[1],
                    exact[1],
                    (got[1] - exact[1]).abs() / exact[1],
                );
                got
            })
            .collect();
        // The stated bound: each rule is within twice its distance to the rule on halved
        // subcells of the exact value (the error falls by 4 per halving: Richardson's 4/3).
        for w in rules.windows(2) {
            for n in 0..2 {
                let (off, step) = ((w[0][n] - exact[n]).abs(), (w[0][n] - w[1][n]).abs());
                assert!(
                    off <= 2.0 * step,
                    "{what} norm {n}: {off:e} off, {step:e} per halving"
                );
            }
        }
        (0..2)
            .map(|n| (rules[0][n] - exact[n]).abs() / exact[n])
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_simplex_mesh_of_the_bars_has_its_closed_form_errors_within_the_quadrature_bound() {
        // f multilinear: the fine Q1 reference reproduces it exactly, P1 does not; so the pair's
        // error is ‖I_P1 f − f‖, computed exactly on the simplices.
        for d in [2, 3] {
            let external = split_bar(d, 5);
            let u_h = nodal(external.points(), d, &multilinear(d).0);
            within_bound(&external, &u_h, &format!("{d}D split"));
        }
    }

    #[test]
    fn the_scripts_unstructured_simplex_meshes_read_cover_the_box_and_meet_their_bound() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mesh");
        for (d, file) in [(2, "bar2d-triangles.vtu"), (3, "bar3d-tetrahedra.vtu")] {
            let snapshot = read_snapshot(&dir.join(file)).unwrap();
            let Some(Topology::Cells(cells)) = &snapshot.topology else {
                panic!("{file} has cells")
            };
            let external = ElementMesh::of_cells(d, snapshot.points.clone(), cells).unwrap();
            check_domain(&external, bar(d, 5).lengths(), 0.0).unwrap();
            let u_h: Vec<f64> = snapshot
                .array("displacement")
                .unwrap()
                .values
                .chunks(3)
                .flat_map(|row| row[..d].to_vec())
                .collect();
            let off = within_bound(&external, &u_h, file);
            assert!(off < 0.05, "{file}: {off:e}");
        }
    }

    #[test]
    fn a_mesh_that_does_not_cover_the_box_is_refused_naming_what_is_off() {
        for d in [2, 3] {
            let lengths: Vec<f64> = bar(d, 5).lengths().to_vec();
            let whole = split_bar(d, 5);
            check_domain(&whole, &lengths, 0.0).unwrap();
            check_domain(&ElementMesh::of_box(&bar(d, 5)), &lengths, 0.0).unwrap();
            // A hole: the first cell left out (the bounding box is still the box's).
            let mut cells = whole.cells().to_vec();
            cells.remove(0);
            let holed = ElementMesh::new(d, whole.points().to_vec(), cells).unwrap();
            let why = check_domain(&holed, &lengths, 0.0).unwrap_err();
            assert!(why.contains("leave a hole or overlap"), "{why}");
            // A mesh of a longer bar.
            let mut points = whole.points().to_vec();
            for p in &mut points {
                p[d - 1] *= 1.01;
            }
            let longer = ElementMesh::new(d, points, whole.cells().to_vec()).unwrap();
            let why = check_domain(&longer, &lengths, 0.0).unwrap_err();
            assert!(why.contains(&format!("along x{d}")), "{why}");
        }
    }
}
