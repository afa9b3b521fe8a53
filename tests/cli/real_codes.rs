//! Other codes' box runs as those codes write them, and runs that must not pass.
//!
//! - **DOLFINx 0.5.2** (`dolfinx.io.VTKFile`: a `.pvd` of `.pvtu` files, each pointing to one
//!   `_p0_*.vtu` piece, no `byte_order`, ASCII with 16 significant digits) and **GetFEM 5.4.2**
//!   (`MeshFem.export_to_vtu`: `Float32` points and data, ASCII with 6 significant digits or base64
//!   with GetFEM's own headers; the `.pvd` written by the script), committed as they wrote them
//!   (`tests/data/external/dolfinx/`, `getfem-vtu/`, by `scripts/dolfinx_bar2d.py` and
//!   `scripts/getfem_bar2d.py`), verify with the errors of the harness's own run of the same case
//!   to the precision of their files. So do DOLFINx's and legacy FEniCS 2019.2's `XDMFFile`
//!   (`tests/data/external/dolfinx-xdmf/`, `fenics-xdmf/`, by `scripts/dolfinx_bar2d.py --writer
//!   xdmf` and `scripts/fenics_bar2d.py`: XDMF 3 with HDF5 heavy data, the mesh included by
//!   `xi:include`); a broken one is refused naming the file and what is off.
//! - The same two codes on their own triangle meshes (`dolfinx-triangles/`, `getfem-triangles/`)
//!   verify on their own mesh, their contact force the resultant of the multipliers they wrote.
//! - A series that went NaN or infinite, multipliers of the wrong sign or off the contact face
//!   are refused naming the file, the array, the point and the time.
//! - A parallel grid's pieces are joined, a ghost node kept once, and refused where the pieces
//!   disagree on it.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common::{expect_error, signorini, success_stdout, test_cache};
use crate::verify_box::{
    errors, read_json, rewrite_collection_with, run_case_every_step, run_every_step, s,
    scene_at_levels, scratch, write_collection, Encoding,
};
use signorini::harness::external::nodal_snapshot::PointArray;
use signorini::harness::external::pvd::{read_collection, read_snapshot};

/// The fixtures' directory.
fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/external")
}

/// `signorini verify scene file --code code` of one case, the velocity and multiplier arrays
/// named, into `out`: its verify.json.
fn verify_as(
    scene: &Path,
    file: &Path,
    code: &str,
    (scheme, multiplier): (&str, &str),
    cache: &Path,
    out: &Path,
) -> Value {
    success_stdout(&signorini(&[
        "verify",
        s(scene),
        s(file),
        "--code",
        code,
        "--code-version",
        "as-written",
        "--scheme",
        scheme,
        "--mass",
        "standard",
        "--velocity",
        "velocity",
        "--multiplier",
        multiplier,
        "--cache",
        s(cache),
        "--out",
        s(out),
    ]));
    read_json(&out.join("verify.json"))
}

/// The largest relative difference between two lists of per-norm errors (the same norms).
fn largest_relative_difference(a: &[(String, Vec<f64>)], b: &[(String, Vec<f64>)]) -> f64 {
    assert_eq!(
        a.iter().map(|(n, _)| n).collect::<Vec<_>>(),
        b.iter().map(|(n, _)| n).collect::<Vec<_>>()
    );
    a.iter()
        .zip(b)
        .flat_map(|((_, x), (_, y))| x.iter().zip(y))
        .map(|(x, y)| (x - y).abs() / y.abs())
        .fold(0.0, f64::max)
}

/// Each fixture, the scheme it solved, the name of its multiplier array and how close its
/// errors must be to the harness's: the precision of its numbers times 20, the ratio of the
/// displacement (0.2) to its errors (1e-2) at level 10, for the files that round the solution
/// (GetFEM's 6 digits in ASCII, its `Float32` in base64); 1e-10 for DOLFINx's 16 digits, where
/// two double-precision solves of the same problem part by round-off first.
const FIXTURES: [(&str, &str, &str, f64); 7] = [
    (
        "dolfinx-xdmf/dolfinx-bar2d-crank-nicolson-standard-level10.xdmf",
        "crank-nicolson",
        "contact_multiplier",
        1e-10,
    ),
    (
        "fenics-xdmf/fenics-bar2d-crank-nicolson-standard-level10.xdmf",
        "crank-nicolson",
        "contact_multiplier",
        1e-10,
    ),
    (
        "dolfinx/dolfinx-bar2d-crank-nicolson-standard-level10.pvd",
        "crank-nicolson",
        "contact_multiplier",
        1e-10,
    ),
    (
        "dolfinx/dolfinx-bar2d-backward-euler-standard-level10.pvd",
        "backward-euler",
        "contact_multiplier",
        1e-10,
    ),
    (
        "getfem-vtu/getfem-crank-nicolson-standard-nx10.pvd",
        "crank-nicolson",
        "multiplier",
        20.0 * 5e-6,
    ),
    (
        "getfem-vtu/getfem-backward-euler-standard-nx10.pvd",
        "backward-euler",
        "multiplier",
        20.0 * 5e-6,
    ),
    (
        "getfem-vtu/getfem-crank-nicolson-standard-nx10-binary.pvd",
        "crank-nicolson",
        "multiplier",
        20.0 * 6e-8,
    ),
];

#[test]
fn dolfinx_and_getfem_files_as_written_verify_with_the_harness_errors() {
    let dir = scratch("real-codes");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10]);
    let cache = dir.join("references");
    for scheme in ["crank-nicolson", "backward-euler"] {
        let own = run_case_every_step(&scene, scheme, "standard", 10, &dir.join(scheme));
        let harness = verify_as(
            &scene,
            &own,
            "signorini",
            (scheme, "contact_multiplier"),
            &cache,
            &dir.join(format!("verify-{scheme}")),
        );
        let expected = errors(&harness["series"][0]["rates"]);
        for (k, (file, _, multiplier, tolerance)) in
            FIXTURES.iter().enumerate().filter(|(_, f)| f.1 == scheme)
        {
            let code = file.split('/').next().unwrap();
            let verified = verify_as(
                &scene,
                &fixtures().join(file),
                code,
                (scheme, multiplier),
                &cache,
                &dir.join(format!("verify-{k}")),
            );
            let series = &verified["series"][0];
            let found = errors(&series["rates"]);
            let difference = largest_relative_difference(&found, &expected);
            assert!(
                difference <= *tolerance,
                "{file}: errors {difference:e} from the harness's, above {tolerance:e}"
            );
            assert!(series["not_computed"].as_array().is_none_or(Vec::is_empty));
        }
    }
}

/// DOLFINx's default triangles (one diagonal per square) and GetFEM's regular simplices
/// (alternating diagonals) of the 2D bar, Crank–Nicolson/standard at level 10, as those codes
/// wrote them (`tests/data/external/dolfinx-triangles/`, `getfem-triangles/`, by
/// `scripts/dolfinx_bar2d.py --cell triangle` and `scripts/getfem_bar2d.py --cell triangle
/// --binary`: VTK cell types 69 and 5), verify on their own mesh: 20 triangles, every norm
/// computed (the energy on their cells, the contact force as the resultant over the face), and
/// the resultant at each sample the sum of the multipliers the file holds.
#[test]
fn triangle_files_as_written_verify_on_their_own_mesh() {
    let dir = scratch("real-triangles");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10]);
    let cache = dir.join("references");
    for (code, file, multiplier) in [
        (
            "dolfinx",
            "dolfinx-triangles/dolfinx-bar2d-triangle-crank-nicolson-standard-level10.pvd",
            "contact_multiplier",
        ),
        (
            "getfem",
            "getfem-triangles/getfem-triangle-crank-nicolson-standard-nx10-binary.pvd",
            "multiplier",
        ),
    ] {
        let pvd = fixtures().join(file);
        let verified = verify_as(
            &scene,
            &pvd,
            code,
            ("crank-nicolson", multiplier),
            &cache,
            &dir.join(code),
        );
        let series = &verified["series"][0];
        assert!(
            series["not_computed"].as_array().is_none_or(Vec::is_empty),
            "{file}: {}",
            series["not_computed"]
        );
        let record = &series["runs"][0]["own_mesh"];
        assert_eq!(record["mesh"], "own mesh: 20 triangles", "{file}");
        let forces = record["contact"]["force"].as_array().unwrap();
        let entries = read_collection(&pvd).unwrap();
        assert_eq!(forces.len(), entries.len(), "{file}");
        let mut largest = 0.0f64;
        for (force, entry) in forces.iter().zip(&entries) {
            let snapshot = read_snapshot(&entry.file).unwrap();
            let array = snapshot.array(multiplier).unwrap();
            let sum: f64 = array.values.iter().sum();
            let force = force.as_f64().unwrap();
            assert!(
                (force - sum).abs() <= 1e-12 * sum.abs().max(1e-3),
                "{file}: {force} {sum}"
            );
            largest = largest.max(sum.abs());
        }
        assert!(
            largest > 1e-2,
            "{file}: the bar hits the obstacle: {largest}"
        );
    }
}

/// The verify command of the harness's Crank–Nicolson run `pvd` of `scene`.
fn verify_args<'a>(scene: &'a Path, pvd: &'a Path, cache: &'a Path) -> Vec<&'a str> {
    vec![
        "verify",
        s(scene),
        s(pvd),
        "--code",
        "edited",
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

/// A scratch directory `name`, the 2D scene at level 10 in it, its reference cache, and the
/// harness's Crank–Nicolson run at every step (its collection).
fn level_10_run(name: &str) -> (PathBuf, PathBuf, PathBuf, PathBuf) {
    let dir = scratch(name);
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10]);
    let cache = dir.join("references");
    let pvd = run_every_step(&scene, 10, &dir.join("run"));
    (dir, scene, cache, pvd)
}

/// The array `name` of a snapshot.
fn array<'a>(arrays: &'a mut [PointArray], name: &str) -> &'a mut PointArray {
    arrays.iter_mut().find(|a| a.name == name).unwrap()
}

#[test]
fn a_broken_series_is_refused_naming_file_array_point_and_time() {
    let (dir, scene, cache, pvd) = level_10_run("broken");
    let edited = |name: &str, edit: &dyn Fn(usize, &mut Vec<PointArray>)| {
        rewrite_collection_with(&pvd, &dir.join(name), Encoding::Ascii, &|step, snapshot| {
            edit(step, &mut snapshot.arrays)
        })
    };
    // NaN in the displacement from t = 1 on (step 20 of level 10): the run blew up.
    let nan = edited("nan", &|step, arrays| {
        if step >= 20 {
            array(arrays, "displacement").values[3 * 5 + 1] = f64::NAN;
        }
    });
    expect_error(
        &verify_args(&scene, &nan, &cache),
        2,
        &[
            "snapshot-20.vtu",
            "PointData \"displacement\"",
            "point 5",
            "t = 1",
            "NaN",
            "finite numbers",
        ],
    );
    // An infinite velocity at one step.
    let inf = edited("inf", &|step, arrays| {
        if step == 30 {
            array(arrays, "velocity").values[0] = f64::INFINITY;
        }
    });
    expect_error(
        &verify_args(&scene, &inf, &cache),
        2,
        &[
            "snapshot-30.vtu",
            "PointData \"velocity\"",
            "point 0",
            "inf",
        ],
    );
    // Multipliers of the other sign convention (λ ≥ 0).
    let flipped = edited("flipped", &|_, arrays| {
        for l in &mut array(arrays, "contact_multiplier").values {
            *l = -*l;
        }
    });
    expect_error(
        &verify_args(&scene, &flipped, &cache),
        2,
        &["multipliers", "λ ≤ 0", "opposite sign"],
    );
    // A multiplier on a node of the clamped face, not a contact node.
    let off_face = edited("off-face", &|step, arrays| {
        if step == 5 {
            let multipliers = &mut array(arrays, "contact_multiplier").values;
            let last = multipliers.len() - 1;
            multipliers[last] = -0.5;
        }
    });
    expect_error(
        &verify_args(&scene, &off_face, &cache),
        2,
        &[
            "snapshot-5.vtu",
            "contact_multiplier",
            "off the contact face",
        ],
    );
}

/// A `.vtu` of one piece with `points` and the point arrays `arrays`, no cells, ASCII, without
/// `byte_order` (as DOLFINx writes its pieces).
fn ascii_piece(points: &[[f64; 3]], arrays: &[PointArray]) -> String {
    let numbers = |v: &mut dyn Iterator<Item = f64>| {
        v.map(|x| format!("{x:?}")).collect::<Vec<_>>().join(" ")
    };
    let mut data = String::new();
    for a in arrays {
        data += &format!(
            "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" \
             format=\"ascii\">{}</DataArray>\n",
            a.name,
            a.components,
            numbers(&mut a.values.iter().copied())
        );
    }
    format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\">\n\
         <UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"0\">\n<PointData>\n\
         {data}</PointData>\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" \
         format=\"ascii\">{}</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" \
         Name=\"connectivity\" format=\"ascii\"></DataArray>\n<DataArray type=\"Int64\" \
         Name=\"offsets\" format=\"ascii\"></DataArray>\n<DataArray type=\"UInt8\" \
         Name=\"types\" format=\"ascii\"></DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n\
         </VTKFile>\n",
        points.len(),
        numbers(&mut points.iter().flatten().copied())
    )
}

/// The harness's run `pvd` written as a parallel grid per step into `dir`: two pieces, the
/// points with x2 ≤ ½ and those with x2 ≥ ½ (the row x2 = ½ in both, as a ghost), each step a
/// `.pvtu` without `byte_order` naming its pieces; `edit` changes the second piece's arrays.
/// Returns the collection.
fn split_collection(pvd: &Path, dir: &Path, edit: &dyn Fn(&mut [PointArray])) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let mut datasets = Vec::new();
    for (step, entry) in read_collection(pvd).unwrap().iter().enumerate() {
        let snapshot = read_snapshot(&entry.file).unwrap();
        let mut names = Vec::new();
        for (k, keep) in [|y: f64| y <= 0.5, |y: f64| y >= 0.5].iter().enumerate() {
            let kept: Vec<usize> = (0..snapshot.points.len())
                .filter(|&i| keep(snapshot.points[i][1]))
                .collect();
            let points: Vec<[f64; 3]> = kept.iter().map(|&i| snapshot.points[i]).collect();
            let mut arrays: Vec<PointArray> = snapshot
                .arrays
                .iter()
                .map(|a| PointArray {
                    name: a.name.clone(),
                    components: a.components,
                    epsilon: a.epsilon,
                    values: kept
                        .iter()
                        .flat_map(|&i| &a.values[i * a.components..(i + 1) * a.components])
                        .copied()
                        .collect(),
                })
                .collect();
            if k == 1 {
                edit(&mut arrays);
            }
            let name = format!("grid_p{k}_{step:06}.vtu");
            std::fs::write(dir.join(&name), ascii_piece(&points, &arrays)).unwrap();
            names.push(name);
        }
        let pvtu = format!("grid{step:06}.pvtu");
        let pieces: String = names
            .iter()
            .map(|n| format!("<Piece Source=\"{n}\"/>\n"))
            .collect();
        std::fs::write(
            dir.join(&pvtu),
            format!(
                "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\">\n\
                 <PUnstructuredGrid GhostLevel=\"1\">\n<PPoints>\n<PDataArray type=\"Float64\" \
                 NumberOfComponents=\"3\"/>\n</PPoints>\n{pieces}</PUnstructuredGrid>\n\
                 </VTKFile>\n"
            ),
        )
        .unwrap();
        datasets.push((entry.time, pvtu));
    }
    write_collection(&dir.join("grid.pvd"), &datasets)
}

#[test]
fn a_parallel_grids_pieces_are_joined_and_a_disagreeing_ghost_is_refused() {
    let (dir, scene, cache, pvd) = level_10_run("pieces");
    let ascii = rewrite_collection_with(&pvd, &dir.join("ascii"), Encoding::Ascii, &|_, _| {});
    let split = split_collection(&pvd, &dir.join("split"), &|_| {});
    let verified = |file: &Path, out: &str| {
        let out = dir.join(out);
        let mut args = verify_args(&scene, file, &cache);
        args.extend(["--out", s(&out)]);
        success_stdout(&signorini(&args));
        errors(&read_json(&out.join("verify.json"))["series"][0]["rates"])
    };
    assert_eq!(
        verified(&split, "verify-split"),
        verified(&ascii, "verify-ascii"),
        "the joined pieces are not the whole grid"
    );
    let disagreeing = split_collection(&pvd, &dir.join("disagreeing"), &|arrays| {
        array(arrays, "displacement").values[1] += 1e-3;
    });
    expect_error(
        &verify_args(&scene, &disagreeing, &cache),
        2,
        &[
            "grid_p1_000000.vtu",
            "PointData \"displacement\"",
            "the piece that also holds this point",
        ],
    );
}

#[test]
fn a_second_verify_of_a_scene_reads_the_reference_the_first_kept() {
    let dir = scratch("second-verify");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10]);
    let file = fixtures().join(FIXTURES[0].0);
    let args = [
        "verify",
        s(&scene),
        s(&file),
        "--code",
        "dolfinx",
        "--code-version",
        "0.5.2",
    ];
    let said = success_stdout(&signorini(&args));
    let kept = format!("kept the reference in {}", test_cache().display());
    assert!(
        said.contains("computing it") && said.contains(&kept),
        "{said}"
    );
    let said = success_stdout(&signorini(&args));
    assert!(!said.contains("computing it"), "{said}");
    let read = format!("read the reference from {}", test_cache().display());
    assert!(said.contains(&read), "{said}");
    let _ = std::fs::remove_dir_all(test_cache());
}

#[test]
fn a_box_series_is_rerun_as_declared_and_a_wrong_declaration_marks_it() {
    let dir = scratch("declared");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10]);
    let cache = dir.join("references");
    let check = |file: &str, multiplier: &str, declared: &str| -> (Value, String) {
        let out = dir.join(format!("{declared}-{}", file.replace('/', "-")));
        let verified = verify_as(
            &scene,
            &fixtures().join(file),
            file.split('/').next().unwrap(),
            (declared, multiplier),
            &cache,
            &out,
        );
        let differences = verified["series"][0]["step_differences"][0].clone();
        assert_eq!(differences["samples"], 41, "{differences}");
        let markdown = std::fs::read_to_string(out.join("verify.md")).unwrap();
        (differences, markdown)
    };
    let largest = |differences: &Value| -> f64 {
        ["displacement", "velocity", "multiplier"]
            .iter()
            .map(|q| differences[q].as_f64().unwrap())
            .fold(0.0, f64::max)
    };
    let dolfinx = "dolfinx/dolfinx-bar2d-crank-nicolson-standard-level10.pvd";
    // DOLFINx's Crank–Nicolson is the harness's to round-off (its file has 16 digits) ...
    let (as_run, markdown) = check(dolfinx, "contact_multiplier", "crank-nicolson");
    assert!(largest(&as_run) <= 1e-12, "{as_run}");
    assert_eq!(as_run["tolerance"].as_f64(), Some(1e-10));
    assert!(markdown.contains("| yes (bound 1e-10) |"), "{markdown}");
    assert!(
        !markdown.contains("differs from its declared"),
        "{markdown}"
    );
    // ... GetFEM's Float32 file is, to a thousand of its epsilons ...
    let getfem = "getfem-vtu/getfem-crank-nicolson-standard-nx10-binary.pvd";
    let (single, markdown) = check(getfem, "multiplier", "crank-nicolson");
    let bound = 1e3 * f64::from(f32::EPSILON);
    assert_eq!(single["tolerance"].as_f64(), Some(bound));
    assert!(largest(&single) <= bound, "{single}");
    assert!(markdown.contains("| yes (bound 1e-4) |"), "{markdown}");
    // ... and DOLFINx's Crank–Nicolson declared as backward Euler is not: the series is marked
    // in both tables and its rerun row.
    let (misdeclared, markdown) = check(dolfinx, "contact_multiplier", "backward-euler");
    assert!(largest(&misdeclared) >= 1e-2, "{misdeclared}");
    assert!(markdown.contains("| **no** (bound 1e-10) |"), "{markdown}");
    let marked = "(**differs from its declared scheme and mass: ";
    assert!(markdown.matches(marked).count() >= 3, "{markdown}");
}

/// Every encoding VTK 9.1's own writers produce (`tests/data/external/vtk-encodings/`, by
/// `scripts/vtk_encodings.py` from `source.vtu`, a snapshot the harness wrote) reads back as the
/// source: the same points and arrays, bit for bit in `Float64`, the source rounded to `Float32`
/// (within half a unit of `f32` rounding) in `Float32`; the parallel grid's two pieces joined
/// into the source's points, its ghost nodes kept once.
#[test]
fn every_encoding_vtk_writes_reads_back_as_the_source() {
    let dir = fixtures().join("vtk-encodings");
    let source = read_snapshot(&dir.join("source.vtu")).unwrap();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy();
            (name.ends_with(".vtu") && !name.starts_with("parallel_") && name != "source.vtu")
                || name.ends_with(".pvtu")
        })
        .collect();
    files.sort();
    assert!(files.len() >= 48, "{} files", files.len());
    let mut failures = Vec::new();
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let read = match read_snapshot(file) {
            Ok(read) => read,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        let single = name.contains("f32");
        let close = |a: f64, b: f64| {
            if single {
                (a - b).abs() <= 0.5 * f64::from(f32::EPSILON) * b.abs().max(f64::MIN_POSITIVE)
            } else {
                a.to_bits() == b.to_bits()
            }
        };
        // The source's points and arrays, in the file's point order.
        let position = |p: &[f64; 3]| {
            source
                .points
                .iter()
                .position(|q| q.iter().zip(p).all(|(&a, &b)| close(b, a)))
        };
        let order: Vec<Option<usize>> = read.points.iter().map(position).collect();
        if read.points.len() != source.points.len() || order.iter().any(Option::is_none) {
            failures.push(format!("{name}: points {:?}", read.points));
            continue;
        }
        for array in &source.arrays {
            let Some(found) = read.array(&array.name) else {
                failures.push(format!("{name}: no array {:?}", array.name));
                continue;
            };
            let c = array.components;
            let differs = order.iter().enumerate().any(|(k, at)| {
                let at = at.unwrap();
                (0..c).any(|i| !close(found.values[k * c + i], array.values[at * c + i]))
            });
            if found.components != c || differs {
                failures.push(format!("{name}: array {:?} differs", array.name));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The DOLFINx XDMF fixture copied into `dir` (its `.xdmf` text edited by `edit`, its `.h5`
/// as written): the copy's `.xdmf`.
fn edited_xdmf(dir: &Path, name: &str, edit: &dyn Fn(String) -> String) -> PathBuf {
    let stem = "dolfinx-bar2d-crank-nicolson-standard-level10";
    let source = fixtures().join("dolfinx-xdmf");
    let target = dir.join(name);
    std::fs::create_dir_all(&target).unwrap();
    std::fs::copy(
        source.join(format!("{stem}.h5")),
        target.join(format!("{stem}.h5")),
    )
    .unwrap();
    let text = std::fs::read_to_string(source.join(format!("{stem}.xdmf"))).unwrap();
    let xdmf = target.join(format!("{stem}.xdmf"));
    std::fs::write(&xdmf, edit(text)).unwrap();
    xdmf
}

#[test]
fn a_broken_xdmf_series_is_refused_naming_what_is_off() {
    let dir = scratch("broken-xdmf");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10]);
    let cache = dir.join("references");
    let stem = "dolfinx-bar2d-crank-nicolson-standard-level10";
    let at_one = format!("{stem}.h5:/Function/velocity/1</DataItem>");
    // The velocity at t = 1 written inline, one value NaN: the non-finite check names it.
    let nan = edited_xdmf(&dir, "nan", &|text| {
        let values = vec!["0"; 22 * 3].join(" ").replacen('0', "NaN", 1);
        let inline = text.replace(
            &format!("Format=\"HDF\">{at_one}"),
            &format!("Format=\"XML\">{values}</DataItem>"),
        );
        assert_ne!(inline, text, "the fixture writes the velocity at t = 1");
        inline
    });
    expect_error(
        &verify_args(&scene, &nan, &cache),
        2,
        &[&format!("{stem}.xdmf"), "\"velocity\"", "t = 1", "NaN"],
    );
    // Heavy data in a file that is not there.
    let missing = edited_xdmf(&dir, "missing", &|text| {
        text.replace(&at_one, "gone.h5:/Function/velocity/1</DataItem>")
    });
    expect_error(
        &verify_args(&scene, &missing, &cache),
        2,
        &["gone.h5", "\"/Function/velocity/1\"", "unreadable"],
    );
    // A dataset whose shape is not the DataItem's.
    let shape = edited_xdmf(&dir, "shape", &|text| {
        text.replacen(
            "Dimensions=\"22 3\" Format=\"HDF\">",
            "Dimensions=\"22 2\" Format=\"HDF\">",
            1,
        )
    });
    expect_error(
        &verify_args(&scene, &shape, &cache),
        2,
        &["of shape [22, 3] where the DataItem says [22, 2]"],
    );
    // A grid with a geometry of its own, other than the mesh's: a moving mesh is not read.
    let moving = edited_xdmf(&dir, "moving", &|text| {
        let include = "<xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid[@GridType='Uniform'][1]/*[self::Topology or self::Geometry])\" />\n        <Time Value=\"1\" />";
        assert!(text.contains(include));
        text.replacen(
            include,
            &format!(
                "<Geometry GeometryType=\"XY\"><DataItem Dimensions=\"22 2\" Format=\"HDF\">{stem}.h5:/Function/velocity/0</DataItem></Geometry>\n        <Time Value=\"1\" />"
            ),
            1,
        )
    });
    expect_error(
        &verify_args(&scene, &moving, &cache),
        2,
        &["Geometry", "one mesh for every time"],
    );
}

#[test]
fn a_file_a_series_points_to_is_never_quoted() {
    let dir = scratch("pointed-to");
    let secret = "TOKEN=never-echo-this";
    std::fs::write(
        dir.join("secret.txt"),
        format!("{secret}\npassword: hunter2\n"),
    )
    .unwrap();
    std::fs::create_dir_all(dir.join("runs")).unwrap();
    let pvd = dir.join("runs/series.pvd");
    std::fs::write(
        &pvd,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\"><Collection>\
         <DataSet timestep=\"0\" part=\"0\" file=\"../secret.txt\"/></Collection></VTKFile>\n",
    )
    .unwrap();
    let xdmf = dir.join("runs/series.xdmf");
    std::fs::write(
        &xdmf,
        "<Xdmf Version=\"3.0\"><Domain><Grid Name=\"m\"><Geometry GeometryType=\"XY\">\
         <DataItem Dimensions=\"22 2\" Format=\"HDF\">../secret.txt:/g</DataItem></Geometry>\
         <Time Value=\"0\"/></Grid></Domain></Xdmf>\n",
    )
    .unwrap();
    for file in [&pvd, &xdmf] {
        let out = signorini(&[
            "verify",
            "scenes/bar2d.json",
            s(file),
            "--code",
            "x",
            "--code-version",
            "1",
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("secret.txt"), "{stderr}");
        assert!(
            !stderr.contains("never-echo") && !stderr.contains("hunter2"),
            "{stderr}"
        );
    }
}

#[test]
fn a_label_cannot_forge_a_row_of_verify_md_or_the_league() {
    let dir = scratch("forged-label");
    let scene = scene_at_levels(&dir, "scenes/bar2d.json", &[10]);
    let file = fixtures().join("dolfinx-xdmf/dolfinx-bar2d-crank-nicolson-standard-level10.xdmf");
    let entries = dir.join("entries");
    let forged = "mine |\n| forged | row |";
    success_stdout(&signorini(&[
        "verify",
        s(&scene),
        s(&file),
        "--code",
        "dolfinx\n| evil",
        "--code-version",
        "0.5.2",
        "--label",
        forged,
        "--cache",
        s(&dir.join("references")),
        "--out",
        s(&entries.join("entry")),
    ]));
    success_stdout(&signorini(&[
        "league",
        s(&entries),
        "--out",
        s(&dir.join("league")),
    ]));
    for page in [
        entries.join("entry/verify.md"),
        dir.join("league/league.md"),
    ] {
        let text = std::fs::read_to_string(&page).unwrap();
        assert!(
            !text
                .lines()
                .any(|l| l.starts_with("| forged") || l.starts_with("| evil")),
            "{}: {text}",
            page.display()
        );
        assert!(text.contains("mine \\| \\| forged \\| row \\|"), "{text}");
    }
}
