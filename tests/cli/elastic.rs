//! The 2D/3D bars of the note from the command line: box scenes run and write VTK files, and
//! bad box input is rejected naming the field. (The θ-method's energy balance on the boxes is in
//! `tests/unit/energy_balance.rs`.)

use crate::common;

use std::path::Path;

use common::{expect_error, signorini, success_stdout};

#[test]
fn a_2d_box_scene_runs_and_writes_vtk_files() {
    let out = std::env::temp_dir().join(format!("signorini-box-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let out_str = out.to_string_lossy().into_owned();
    let o = signorini(&[
        "run",
        "scenes/bar2d.json",
        "--scheme",
        "crank-nicolson",
        "--mass",
        "redistributed",
        "--nx",
        "20",
        "--out",
        &out_str,
    ]);
    success_stdout(&o);
    for t in ["0.500", "1.000", "1.500", "2.000"] {
        let text = std::fs::read_to_string(out.join(format!("field-t{t}.vtu"))).unwrap();
        let doc = roxmltree::Document::parse(&text).unwrap();
        let piece = doc.descendants().find(|n| n.has_tag_name("Piece")).unwrap();
        assert_eq!(piece.attribute("NumberOfCells"), Some("40"));
        assert_eq!(piece.attribute("NumberOfPoints"), Some("63"));
        let names: Vec<&str> = doc
            .descendants()
            .filter(|n| n.has_tag_name("DataArray"))
            .filter_map(|n| n.attribute("Name"))
            .collect();
        for field in ["displacement", "velocity", "von_mises"] {
            assert!(names.contains(&field), "{field} missing at t = {t}");
        }
    }
    let contact = std::fs::read_to_string(out.join("contact.csv")).unwrap();
    assert!(contact.starts_with("time,mean_gap,centre_gap,total_force,centre_multiplier"));
}

fn edited_box_scene(from: &str, to: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/bar3d.json")).unwrap();
    assert!(text.contains(from));
    let path = std::env::temp_dir().join(format!(
        "signorini-box-scene-{}-{}.json",
        std::process::id(),
        from.len() + to.len()
    ));
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn bad_box_input_is_rejected_naming_the_field() {
    let cases: [(&str, &str, &[&str]); 6] = [
        (
            "\"lame_mu\": 0.5",
            "\"lame_mu\": 0.0",
            &["material.lame_mu"],
        ),
        (
            "\"lame_lambda\": 0.25",
            "\"lame_lambda\": -0.5",
            &["material.lame_lambda"],
        ),
        (
            "\"reference\": \"none\"",
            "\"reference\": { \"exact\": \"at-rest\" }",
            &["reference"],
        ),
        ("\"clamped\"", "\"free\"", &["boundary.far_end", "clamped"]),
        ("[0.1, 0.1, 1.0]", "[0.1, 0.0, 1.0]", &["geometry.lengths"]),
        ("\"horizon\": 2.0", "\"horizon\": -2.0", &["horizon", "> 0"]),
    ];
    for (from, to, needles) in cases {
        let scene = edited_box_scene(from, to);
        expect_error(
            &[
                "run",
                &scene,
                "--scheme",
                "crank-nicolson",
                "--mass",
                "standard",
                "--nx",
                "4",
            ],
            2,
            needles,
        );
    }
    expect_error(
        &[
            "run",
            "scenes/bar3d.json",
            "--scheme",
            "crank-nicolson",
            "--mass",
            "standard",
            "--nx",
            "0",
        ],
        2,
        &["elements"],
    );
    let cache = std::env::temp_dir().join(format!("signorini-bad-cache-{}", std::process::id()));
    let cache = cache.to_string_lossy();
    expect_error(
        &[
            "study",
            "scenes/bar2d.json",
            "--reference-level",
            "100",
            "--cache",
            &cache,
        ],
        2,
        &["reference_level", "multiple of 2"],
    );
    expect_error(
        &[
            "study",
            "scenes/bar2d.json",
            "--levels",
            "10,15",
            "--cache",
            &cache,
        ],
        2,
        &["levels", "nested"],
    );
    let unnested = edited_box_scene("\"reference_level\": 160", "\"reference_level\": 150");
    expect_error(
        &["study", &unnested, "--cache", &cache],
        2,
        &["discretisation.reference_level", "multiple of twice"],
    );
    let without = edited_box_scene("\"reference_level\": 160, ", "");
    expect_error(
        &["study", &without, "--cache", &cache],
        2,
        &["discretisation.reference_level", "fine-mesh reference"],
    );
    expect_error(
        &[
            "study",
            "scenes/bar1d-dirichlet.json",
            "--reference-level",
            "40",
        ],
        2,
        &["box scenes"],
    );
    assert!(
        !Path::new(cache.as_ref()).exists(),
        "nothing cached on bad input"
    );
}

/// `--linear-solver` chooses the step solver of a box run, the run saying why (its solver plan);
/// an unknown one is a usage error naming the option and the allowed values.
#[test]
fn the_linear_solver_is_chosen_on_the_command_line() {
    let args = |solver: &'static str| {
        [
            "run",
            "scenes/bar3d.json",
            "--scheme",
            "crank-nicolson",
            "--mass",
            "redistributed",
            "--nx",
            "10",
            "--linear-solver",
            solver,
        ]
    };
    // The energies and the largest force to 7 digits (the complementarity residual that follows
    // is round-off and differs).
    let energy = |stdout: String| {
        stdout
            .lines()
            .find_map(|l| {
                l.split("; complementarity")
                    .next()
                    .filter(|_| l.contains("energy"))
            })
            .map(str::to_owned)
            .unwrap()
    };
    let direct = energy(success_stdout(&signorini(&args("direct"))));
    assert_eq!(energy(success_stdout(&signorini(&args("cg")))), direct);
    // `auto` is resolved once, by the solver plan, which says why: this box is below the size
    // from which `auto` takes cg.
    let auto = success_stdout(&signorini(&args("auto")));
    let plan = auto
        .lines()
        .find(|l| l.trim_start().starts_with("solver plan:"))
        .unwrap_or_else(|| panic!("no solver plan line in:\n{auto}"));
    assert!(
        plan.contains("step solver direct (auto:") && plan.contains("contact operator"),
        "{plan}"
    );
    assert_eq!(energy(auto), direct);
    expect_error(
        &args("lu"),
        2,
        &["--linear-solver", "lu", "direct, cg, auto"],
    );
}
