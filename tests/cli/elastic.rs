//! The 2D/3D bars of the note: the θ-method's energy balance (eq. 35) per step with many
//! contact nodes, box scenes run from the command line and write VTK files, and bad box input
//! is rejected naming the field.

use crate::common;

use std::path::Path;

use common::{expect_error, signorini, success_stdout};

use signorini::fem::box_mesh::{BoxMesh, Elasticity};
use signorini::fem::MassVariant;
use signorini::model::Model;
use signorini::schemes::energy_balance::BalanceMonitor;
use signorini::schemes::{integrator, Scheme};

#[test]
fn backward_euler_balance_holds_every_step_in_2d_and_3d() {
    // Eq. (35) with θ = 1 (`energy_balance::theta`):
    // ΔE = −½ΔVᵀMΔV − ½ΔUᵀSΔU − Σ_i Δu_{c_i} λ_i^{n+1}.
    for mesh in [
        BoxMesh::note_2d(2, 16).unwrap(),
        BoxMesh::note_3d(2, 2, 8).unwrap(),
    ] {
        for mass in MassVariant::ALL {
            let model = Model::of_box(&mesh, &Elasticity::NOTE, mass, Some(0.2));
            let d = mesh.dim();
            let u0 = vec![0.0; model.n_dofs()];
            let v0 = mesh.interpolate(|_| {
                let mut v = [0.0; 3];
                v[d - 1] = -0.5;
                v
            });
            let dt = mesh.element_sizes()[d - 1] / 2.0;
            let scheme = Scheme::Theta { theta: 1.0 };
            let mut s = integrator(&model, scheme, dt, &u0, &v0).unwrap();
            let mut monitor = BalanceMonitor::new(&model, scheme, dt);
            monitor.observe(s.as_ref());
            let e0 = s.energy().value;
            let mut worst: f64 = 0.0;
            let mut touched = false;
            for _ in 0..((1.5 / dt).round() as usize) {
                s.advance().unwrap();
                touched |= s.multiplier().value.iter().any(|&l| l < 0.0);
                let balance = monitor.observe(s.as_ref()).expect("one step further");
                worst = worst.max(balance.residual().abs() / e0);
            }
            assert!(touched, "{d}D {mass}: no contact");
            assert!(worst < 1e-12, "{d}D {mass}: residual {worst:e}");
        }
    }
}

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
    for t in ["0.5", "1", "1.5", "2"] {
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
