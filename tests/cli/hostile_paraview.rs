//! Hostile ParaView and XDMF input (issue 55, item 3), each tried on `signorini verify` as a
//! user would hand it over: the inputs that made the VTK library it used panic, inflate without
//! bound or drop an array silently, and the documents nested deep enough to overflow a parser's
//! stack. Every one exits 2 naming the file and what is off, watched for time and peak memory,
//! and leaves the user's files as they were.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::verify_box::scene_at_levels;
use crate::watched::{scratch, watched};

/// The slowest any of these runs may take.
const SECONDS: u64 = 20;
/// The largest peak resident size (kB) any of them may reach: 256 MiB, a small fraction of what
/// the bombs below would inflate to.
const PEAK_KB: u64 = 256 * 1024;

/// VTK 9.1's own snapshot of the 2D bar at level 10 in `encoding` (`tests/data/external/vtk-encodings`).
fn vtk_snapshot(encoding: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/external/vtk-encodings")
        .join(format!("{encoding}.vtu"));
    std::fs::read_to_string(path).unwrap()
}

/// `text` with the content of its `displacement` array replaced by `content`.
fn with_displacement(text: &str, content: &str) -> String {
    let name = text.find("Name=\"displacement\"").unwrap();
    let start = name + text[name..].find('>').unwrap() + 1;
    let end = start + text[start..].find("</DataArray>").unwrap();
    format!("{}{content}{}", &text[..start], &text[end..])
}

/// A collection in `dir` of the one snapshot `vtu` (written beside it) at t = 0.
fn series_of(dir: &Path, vtu: &str) -> PathBuf {
    std::fs::write(dir.join("s.vtu"), vtu).unwrap();
    let pvd = dir.join("s.pvd");
    std::fs::write(
        &pvd,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n\
         <DataSet timestep=\"0\" part=\"0\" file=\"s.vtu\"/>\n</Collection>\n</VTKFile>\n",
    )
    .unwrap();
    pvd
}

/// Every file of `dir` with its bytes.
fn contents(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            let bytes = std::fs::read(&path).unwrap_or_default();
            (path, bytes)
        })
        .collect();
    files.sort();
    files
}

/// `verify` of the collection `series` (a `.pvd` or `.xdmf`) against a small 2D scene, watched:
/// exits 2 with every needle in its stderr, and the files of the series' directory unchanged.
fn refused(dir: &Path, series: &Path, needles: &[&str]) {
    let scene = scene_at_levels(dir, "scenes/bar2d.json", &[5, 10]);
    let before = contents(series.parent().unwrap());
    let out = watched(
        &[
            "verify",
            &scene.to_string_lossy(),
            &series.to_string_lossy(),
            "--code",
            "hostile",
            "--code-version",
            "0",
            "--cache",
            &dir.join("cache").to_string_lossy(),
        ],
        None,
        SECONDS,
        PEAK_KB,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "{needle:?} not in {stderr}");
    }
    assert_eq!(contents(series.parent().unwrap()), before);
}

#[test]
fn an_empty_base64_array_is_refused_naming_it() {
    let dir = scratch("hostile-paraview", "empty");
    let vtu = with_displacement(&vtk_snapshot("binary-none-uint64-f64"), "");
    refused(
        &dir,
        &series_of(&dir, &vtu),
        &["s.vtu", "PointData \"displacement\"", "past the data's end"],
    );
}

/// The array whose component count is one off is refused by name: it is never dropped, so the
/// velocity is never taken as the displacement.
#[test]
fn an_unreadable_displacement_is_refused_not_replaced_by_the_velocity() {
    let dir = scratch("hostile-paraview", "components");
    let vtu = vtk_snapshot("binary-none-uint64-f64").replacen(
        "Name=\"displacement\" NumberOfComponents=\"3\"",
        "Name=\"displacement\" NumberOfComponents=\"2\"",
        1,
    );
    refused(
        &dir,
        &series_of(&dir, &vtu),
        &[
            "PointData \"displacement\"",
            "a header of 528 bytes where the grid needs 352",
        ],
    );
}

/// A zlib block whose header says it holds the 528 bytes the grid needs, but which inflates to
/// 512 MiB of zeros: inflation stops one byte past the declared size.
#[test]
fn a_zlib_bomb_in_a_compressed_array_is_refused_after_its_declared_size() {
    let dir = scratch("hostile-paraview", "zlib");
    let mut encoder = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    let zeros = vec![0u8; 1 << 20];
    for _ in 0..512 {
        encoder.write_all(&zeros).unwrap();
    }
    let bomb = encoder.finish().unwrap();
    let mut header = Vec::new();
    for word in [1u64, 528, 528, bomb.len() as u64] {
        header.extend_from_slice(&word.to_le_bytes());
    }
    use base64::Engine as _;
    let b64 = base64::engine::general_purpose::STANDARD;
    let content = b64.encode(&header) + &b64.encode(&bomb);
    let vtu = with_displacement(&vtk_snapshot("binary-zlib-uint64-f64"), &content);
    refused(
        &dir,
        &series_of(&dir, &vtu),
        &[
            "PointData \"displacement\"",
            "compressed block 0 inflates to 529 or more bytes where its header says 528",
        ],
    );
}

/// A header claiming 2⁶⁰ blocks is refused before anything is sized by it.
#[test]
fn a_header_of_absurd_sizes_is_refused_before_it_sizes_anything() {
    let dir = scratch("hostile-paraview", "header");
    let mut header = Vec::new();
    for word in [1u64 << 60, 1 << 40, 1 << 40] {
        header.extend_from_slice(&word.to_le_bytes());
    }
    use base64::Engine as _;
    let content = base64::engine::general_purpose::STANDARD.encode(&header);
    let vtu = with_displacement(&vtk_snapshot("binary-zlib-uint64-f64"), &content);
    refused(
        &dir,
        &series_of(&dir, &vtu),
        &[
            "PointData \"displacement\"",
            "where the grid needs 528 bytes",
        ],
    );
}

/// Collections, snapshots and XDMF documents nested 100 000 deep (700 kB) are refused before
/// they are parsed.
#[test]
fn documents_nested_deep_are_refused_before_they_are_parsed() {
    let dir = scratch("hostile-paraview", "nested");
    let deep = format!(
        "<?xml version=\"1.0\"?>\n{}{}",
        "<a>".repeat(100_000),
        "</a>".repeat(100_000)
    );
    let pvd = dir.join("deep.pvd");
    std::fs::write(&pvd, &deep).unwrap();
    refused(&dir, &pvd, &["deep.pvd", "nested more than 64 deep"]);
    let xdmf = dir.join("deep.xdmf");
    std::fs::write(&xdmf, &deep).unwrap();
    refused(&dir, &xdmf, &["deep.xdmf", "nested more than 64 deep"]);
    let vtu = vtk_snapshot("ascii-f64").replacen(
        "<Points>",
        &format!(
            "<Points>{}{}",
            "<a>".repeat(100_000),
            "</a>".repeat(100_000)
        ),
        1,
    );
    refused(
        &dir,
        &series_of(&dir, &vtu),
        &["s.vtu", "nested more than 64 deep"],
    );
}

/// A collection of more datasets than any run writes is refused before its XML tree is built
/// (3 million datasets, 175 MB, took 1.6 GB before): counted in its text first.
#[test]
fn a_collection_of_a_million_datasets_is_refused_before_it_is_parsed() {
    let dir = scratch("hostile-paraview", "datasets");
    let pvd = dir.join("many.pvd");
    let datasets = (1 << 20) + 1;
    let text = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\"><Collection>\n{}</Collection></VTKFile>\n",
        "<DataSet/>\n".repeat(datasets)
    );
    std::fs::write(&pvd, text).unwrap();
    refused(
        &dir,
        &pvd,
        &[
            "many.pvd",
            &format!("{datasets} datasets"),
            "at most 262144 of the body",
        ],
    );
}
