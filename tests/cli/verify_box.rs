//! `signorini verify` on box scenes end to end: the harness's own 2D and 3D runs, written at
//! every step as ParaView collections (`run --fields-every-step`) and rewritten here as ASCII
//! and as appended raw data, verify to the bits of the box study's errors of the same case; a
//! run in the JSON format's box form with fields at some steps only gets the force norm and the
//! displacement errors at those steps; a different mesh, scene or level and a missing step are
//! refused with exit code 2 and the reason.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common::{expect_error, signorini, success_stdout};
use signorini::harness::external::nodal_snapshot::NodalSnapshot;
use signorini::harness::external::pvd::{read_collection, read_snapshot};

/// A box scene of the repository made small: study levels 5 and 10, reference on 40 (nested:
/// one element across at levels 5 and 10, four at 40), no ensemble.
fn small_scene(dir: &Path, scene: &str) -> PathBuf {
    scene_at_levels(dir, scene, &[5, 10])
}

/// The box scene `scene` with the study levels `levels` and the reference on 40, no ensemble.
pub(crate) fn scene_at_levels(dir: &Path, scene: &str, levels: &[usize]) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut s: Value =
        serde_json::from_str(&std::fs::read_to_string(root.join(scene)).unwrap()).unwrap();
    let d = &mut s["discretisation"];
    d["levels"] = serde_json::json!(levels);
    d["reference_level"] = serde_json::json!(40);
    d.as_object_mut().unwrap().remove("sensitivity");
    let path = dir.join("scene.json");
    std::fs::write(&path, s.to_string()).unwrap();
    path
}

pub(crate) fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "signorini-verify-box-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub(crate) fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Crank–Nicolson with the standard mass on `nx` elements, its fields at every step in `out`.
pub(crate) fn run_every_step(scene: &Path, nx: usize, out: &Path) -> PathBuf {
    run_case_every_step(scene, "crank-nicolson", "standard", nx, out)
}

/// `scheme` with `mass` on `nx` elements, its fields at every step in `out`.
pub(crate) fn run_case_every_step(
    scene: &Path,
    scheme: &str,
    mass: &str,
    nx: usize,
    out: &Path,
) -> PathBuf {
    let nx = nx.to_string();
    success_stdout(&signorini(&[
        "run",
        s(scene),
        "--scheme",
        scheme,
        "--mass",
        mass,
        "--nx",
        &nx,
        "--out",
        s(out),
        "--fields-every-step",
    ]));
    out.join("fields.pvd")
}

/// The errors of every norm of the series `k` of a verify.json, or of the case `(scheme
/// family, mass)` of an elastic study's JSON.
pub(crate) fn errors(rates: &Value) -> Vec<(String, Vec<f64>)> {
    rates
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let e = r["errors"].as_array().unwrap();
            (
                r["norm"].as_str().unwrap().to_string(),
                e.iter().map(|x| x.as_f64().unwrap()).collect(),
            )
        })
        .collect()
}

pub(crate) fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The errors of Crank–Nicolson with the standard mass in the study of `scene` (a
/// `dimension`-D box) run with the reference cache `cache` into `out`.
fn study_errors(
    scene: &Path,
    cache: &Path,
    out: &Path,
    dimension: usize,
) -> Vec<(String, Vec<f64>)> {
    success_stdout(&signorini(&[
        "study",
        s(scene),
        "--cache",
        s(cache),
        "--out",
        s(out),
    ]));
    let study = read_json(&out.join(format!("elastic-{dimension}d.json")));
    let case = study["study"]["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| {
            c["case"]["mass"] == "standard"
                && c["case"]["scheme"]["family"] == "newmark"
                && c["case"]["scheme"]["beta"] == 0.25
        })
        .expect("the study has crank-nicolson/standard");
    errors(&case["rates"])
}

/// How a snapshot's arrays are written by [`rewrite`].
#[derive(Clone, Copy)]
pub(crate) enum Encoding {
    /// Inline ASCII, every number with the digits that read it back.
    Ascii,
    /// One appended block of raw little-endian bytes, `UInt64` headers.
    AppendedRaw,
}

/// An edit of a snapshot before it is written again: its step and the snapshot.
pub(crate) type Edit<'a> = &'a dyn Fn(usize, &mut NodalSnapshot);

/// `src` (a snapshot the harness wrote, at step `step`) written again to `dst` in `encoding`,
/// with its points, its cells (as vtkio reads them) and its point arrays, after `edit`: another
/// writer than the harness's.
fn rewrite(src: &Path, dst: &Path, encoding: Encoding, step: usize, edit: Edit<'_>) {
    use vtkio::model::{DataSet, Piece, VertexNumbers};
    let mut snapshot = read_snapshot(src).unwrap();
    edit(step, &mut snapshot);
    let vtk = vtkio::Vtk::import(src).unwrap();
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("an unstructured grid")
    };
    let Piece::Inline(piece) = &pieces[0] else {
        panic!("inline")
    };
    let VertexNumbers::XML {
        connectivity,
        offsets,
    } = &piece.cells.cell_verts
    else {
        panic!("XML cells")
    };
    let types: Vec<u8> = piece.cells.types.iter().map(|t| *t as u8).collect();
    let points: Vec<f64> = snapshot.points.iter().flatten().copied().collect();
    let mut appended: Vec<u8> = Vec::new();
    let mut array = |kind: &str, name: &str, components: usize, text: Vec<String>, raw: Vec<u8>| {
        let name = if name.is_empty() {
            String::new()
        } else {
            format!(" Name=\"{name}\"")
        };
        match encoding {
            Encoding::Ascii => format!(
                "<DataArray type=\"{kind}\"{name} NumberOfComponents=\"{components}\" \
                 format=\"ascii\">{}</DataArray>\n",
                text.join(" ")
            ),
            Encoding::AppendedRaw => {
                let offset = appended.len();
                appended.extend((raw.len() as u64).to_le_bytes());
                appended.extend(raw);
                format!(
                    "<DataArray type=\"{kind}\"{name} NumberOfComponents=\"{components}\" \
                     format=\"appended\" offset=\"{offset}\"/>\n"
                )
            }
        }
    };
    let f64s = |v: &[f64]| -> (Vec<String>, Vec<u8>) {
        (
            v.iter().map(|x| format!("{x:?}")).collect(),
            v.iter().flat_map(|x| x.to_le_bytes()).collect(),
        )
    };
    let u64s = |v: &[u64]| -> (Vec<String>, Vec<u8>) {
        (
            v.iter().map(u64::to_string).collect(),
            v.iter().flat_map(|x| x.to_le_bytes()).collect(),
        )
    };
    let (pt, pr) = f64s(&points);
    let points_xml = array("Float64", "", 3, pt, pr);
    let (ct, cr) = u64s(connectivity);
    let (ot, or) = u64s(offsets);
    let cells_xml = array("UInt64", "connectivity", 1, ct, cr)
        + &array("UInt64", "offsets", 1, ot, or)
        + &array(
            "UInt8",
            "types",
            1,
            types.iter().map(u8::to_string).collect(),
            types.clone(),
        );
    let mut point_data = String::new();
    for a in &snapshot.arrays {
        let (t, r) = f64s(&a.values);
        point_data += &array("Float64", &a.name, a.components, t, r);
    }
    let mut xml = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece \
         NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<PointData>\n{point_data}</PointData>\n\
         <Points>\n{points_xml}</Points>\n<Cells>\n{cells_xml}</Cells>\n</Piece>\n\
         </UnstructuredGrid>\n",
        snapshot.points.len(),
        types.len()
    )
    .into_bytes();
    if let Encoding::AppendedRaw = encoding {
        xml.extend(b"<AppendedData encoding=\"raw\">\n_");
        xml.extend(&appended);
        xml.extend(b"\n</AppendedData>\n");
    }
    xml.extend(b"</VTKFile>\n");
    std::fs::write(dst, xml).unwrap();
}

/// The collection `pvd` with every body snapshot rewritten in `encoding` into `dir`.
fn rewrite_collection(pvd: &Path, dir: &Path, encoding: Encoding) -> PathBuf {
    rewrite_collection_with(pvd, dir, encoding, &|_, _| {})
}

/// [`rewrite_collection`] with each snapshot edited by `edit` first.
pub(crate) fn rewrite_collection_with(
    pvd: &Path,
    dir: &Path,
    encoding: Encoding,
    edit: Edit<'_>,
) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let mut datasets = Vec::new();
    for (k, entry) in read_collection(pvd).unwrap().iter().enumerate() {
        let file = format!("snapshot-{k}.vtu");
        rewrite(&entry.file, &dir.join(&file), encoding, k, edit);
        datasets.push((entry.time, file));
    }
    write_collection(&dir.join("fields.pvd"), &datasets)
}

/// A collection (`.pvd`) at `path` listing `datasets` (time, file) as part 0: its path.
pub(crate) fn write_collection(path: &Path, datasets: &[(f64, String)]) -> PathBuf {
    let mut lines = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n",
    );
    for (time, file) in datasets {
        lines += &format!("<DataSet timestep=\"{time:?}\" part=\"0\" file=\"{file}\"/>\n");
    }
    lines += "</Collection>\n</VTKFile>\n";
    std::fs::write(path, lines).unwrap();
    path.to_path_buf()
}

/// Verifies `files` (one series of Crank–Nicolson with the standard mass) against `scene`
/// with the reference cache `cache`, writing verify.json into `out`.
pub(crate) fn verify(scene: &Path, files: &[&Path], cache: &Path, out: &Path) -> Value {
    let mut args = vec!["verify", s(scene)];
    args.extend(files.iter().map(|f| s(f)));
    args.extend([
        "--code",
        "signorini",
        "--code-version",
        "test",
        "--label",
        "cn-std",
        "--scheme",
        "crank-nicolson",
        "--mass",
        "standard",
        "--velocity",
        "velocity",
        "--multiplier",
        "contact_multiplier",
        "--cache",
        s(cache),
        "--out",
        s(out),
    ]);
    success_stdout(&signorini(&args));
    read_json(&out.join("verify.json"))
}

/// The harness's own runs of `scene` through `.pvd` (its binary, and rewritten as ASCII and as
/// appended raw data) verify to the bits of the box study's errors of the same case.
fn round_trip(scene_file: &str, name: &str) {
    let dir = scratch(name);
    let scene = small_scene(&dir, scene_file);
    let cache = dir.join("references");
    let dimension = if scene_file.contains("3d") { 3 } else { 2 };
    let expected = study_errors(&scene, &cache, &dir.join("study"), dimension);
    let binary: Vec<PathBuf> = [5, 10]
        .iter()
        .map(|&nx| run_every_step(&scene, nx, &dir.join(format!("run{nx}"))))
        .collect();
    for (encoding, label) in [
        (None, "binary"),
        (Some(Encoding::Ascii), "ascii"),
        (Some(Encoding::AppendedRaw), "appended"),
    ] {
        let files: Vec<PathBuf> = match encoding {
            None => binary.clone(),
            Some(e) => binary
                .iter()
                .enumerate()
                .map(|(k, pvd)| rewrite_collection(pvd, &dir.join(format!("{label}{k}")), e))
                .collect(),
        };
        let refs: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
        let verified = verify(&scene, &refs, &cache, &dir.join(format!("verify-{label}")));
        let series = &verified["series"][0];
        assert_eq!(
            errors(&series["rates"]),
            expected,
            "{name} {label}: the verified errors are not the study's"
        );
        assert!(series["not_computed"].as_array().is_none_or(Vec::is_empty));
    }
}

#[test]
fn the_harness_2d_runs_through_pvd_verify_to_the_bits_of_the_study() {
    round_trip("scenes/bar2d.json", "2d");
}

#[test]
fn the_harness_3d_runs_through_pvd_verify_to_the_bits_of_the_study() {
    round_trip("scenes/bar3d.json", "3d");
}

/// The box form with fields at every fourth step and the multipliers at every step: the force
/// norm is the study's to the bits, the displacement and energy norms are not computed (the
/// reasons name what is missing), and the displacement errors at the sampled steps are listed.
#[test]
fn a_json_box_run_with_fields_at_some_steps_gets_the_force_and_the_sampled_errors() {
    let dir = scratch("partial");
    let scene = small_scene(&dir, "scenes/bar2d.json");
    let cache = dir.join("references");
    let expected = study_errors(&scene, &cache, &dir.join("study"), 2);
    let mut files = Vec::new();
    for nx in [5, 10] {
        let pvd = run_every_step(&scene, nx, &dir.join(format!("run{nx}")));
        let mut samples = Vec::new();
        for (k, entry) in read_collection(&pvd).unwrap().iter().enumerate() {
            let snapshot = read_snapshot(&entry.file).unwrap();
            let displacement: Vec<[f64; 2]> = snapshot
                .array("displacement")
                .unwrap()
                .values
                .chunks(3)
                .map(|c| [c[0], c[1]])
                .collect();
            let multiplier = &snapshot.array("contact_multiplier").unwrap().values;
            let mut sample = serde_json::json!({
                "time": entry.time,
                "multipliers": multiplier[..2],
            });
            if k % 4 == 0 {
                sample["displacement"] = serde_json::json!(displacement);
            }
            samples.push(sample);
        }
        let file = serde_json::json!({
            "format": "signorini-external/2",
            "scene": "bar2d",
            "code": {"name": "signorini", "version": "test"},
            "label": "cn-std sampled",
            "scheme": "crank-nicolson",
            "mass": "standard",
            "mesh": {"lengths": [0.1, 1.0], "elements": [1, nx], "node_order": "x1-fastest"},
            "samples": samples,
        });
        let path = dir.join(format!("sampled-{nx}.json"));
        std::fs::write(&path, file.to_string()).unwrap();
        files.push(path);
    }
    let out = dir.join("verify");
    let stdout = success_stdout(&signorini(&[
        "verify",
        s(&scene),
        s(&files[0]),
        s(&files[1]),
        "--cache",
        s(&cache),
        "--out",
        s(&out),
    ]));
    let verified = read_json(&out.join("verify.json"));
    let series = &verified["series"][0];
    let got = errors(&series["rates"]);
    assert_eq!(got.len(), 1, "only the force norm is computed: {got:?}");
    assert_eq!(
        got[0],
        expected
            .iter()
            .find(|(n, _)| n == "lambda_L2")
            .unwrap()
            .clone()
    );
    let reasons = series["not_computed"].to_string();
    assert!(
        reasons.contains("displacement fields at every step"),
        "{reasons}"
    );
    assert!(
        reasons.contains("velocity fields at every step"),
        "{reasons}"
    );
    let sampled = series["runs"][0]["displacement_at_samples"]
        .as_array()
        .unwrap();
    assert_eq!(sampled.len(), 6, "steps 0, 4, …, 20 of level 5");
    assert!(stdout.contains("## Displacement errors at the samples with fields"));
}

/// A different mesh, scene or level, and a missing step: exit code 2, the reason named.
#[test]
fn a_box_run_that_is_not_the_scenes_is_refused_with_the_reason() {
    let dir = scratch("refused");
    let scene = small_scene(&dir, "scenes/bar2d.json");
    let cache = dir.join("references");
    let pvd = run_every_step(&scene, 5, &dir.join("run5"));
    let ascii = rewrite_collection(&pvd, &dir.join("ascii"), Encoding::Ascii);
    let args = |file: &Path| -> Vec<String> {
        [
            "verify",
            s(&scene),
            s(file),
            "--code",
            "x",
            "--code-version",
            "1",
            "--cache",
            s(&cache),
        ]
        .map(String::from)
        .to_vec()
    };
    let expect = |file: &Path, needles: &[&str]| {
        let a = args(file);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        expect_error(&a, 2, needles);
    };
    // A node moved off the mesh.
    let moved = dir.join("moved");
    std::fs::create_dir_all(&moved).unwrap();
    for entry in std::fs::read_dir(dir.join("ascii")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, moved.join(path.file_name().unwrap())).unwrap();
    }
    let first = moved.join("snapshot-0.vtu");
    let text = std::fs::read_to_string(&first).unwrap();
    std::fs::write(&first, text.replacen("0.1 0.0 0.0", "0.1 0.001 0.0", 1)).unwrap();
    expect(
        &moved.join("fields.pvd"),
        &["Points", "point 1", "the nodes of the scene's Q1 mesh"],
    );
    // A step left out of the collection.
    let collection = std::fs::read_to_string(&ascii).unwrap();
    let gapped = dir.join("ascii").join("gapped.pvd");
    let without: Vec<&str> = collection
        .lines()
        .filter(|l| !l.contains("snapshot-3.vtu"))
        .collect();
    std::fs::write(&gapped, without.join("\n")).unwrap();
    expect(
        &gapped,
        &["timestep", "step 3", "one sample per step of level 5"],
    );
    // A level the scene's study does not have.
    let pvd20 = run_every_step(&scene, 20, &dir.join("run20"));
    expect(
        &pvd20,
        &["nodes", "the scene's Q1 mesh at one of its study levels"],
    );
    // Another scene's run in the box form.
    let other = dir.join("other.json");
    std::fs::write(
        &other,
        serde_json::json!({
            "format": "signorini-external/2",
            "scene": "bar3d",
            "code": {"name": "x", "version": "1"},
            "label": "l",
            "mesh": {"lengths": [0.1, 1.0], "elements": [1, 5], "node_order": "x1-fastest"},
            "samples": [],
        })
        .to_string(),
    )
    .unwrap();
    expect(&other, &["scene", "\"bar2d\""]);
    // A .pvd without the code that wrote it.
    expect_error(
        &["verify", s(&scene), s(&pvd), "--cache", s(&cache)],
        2,
        &["--code", "does not say which code wrote it"],
    );
}

/// A reference missing from the cache is computed only within the limits: over
/// `--max-dof-steps`, exit code 2 naming the limit, and nothing is computed or written.
#[test]
fn a_reference_over_the_limits_is_not_computed() {
    let dir = scratch("over-limits");
    let scene = small_scene(&dir, "scenes/bar2d.json");
    let pvd = run_every_step(&scene, 5, &dir.join("run5"));
    let cache = dir.join("references");
    expect_error(
        &[
            "verify",
            s(&scene),
            s(&pvd),
            "--code",
            "x",
            "--code-version",
            "1",
            "--cache",
            s(&cache),
            "--max-dof-steps",
            "1000",
            "--out",
            s(&dir.join("verified")),
        ],
        2,
        &["--max-dof-steps"],
    );
    assert!(!dir.join("verified").exists(), "nothing is written");
    let cached = std::fs::read_dir(&cache).map_or(0, |d| d.count());
    assert_eq!(cached, 0, "no reference is computed");
}
