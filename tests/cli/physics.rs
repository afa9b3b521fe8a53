//! The physics every run is checked for (issue 53, item 1): `signorini run` prints and
//! `run.json` stores the largest penetration, the largest energy above the start and the
//! contact-force sign, and flags a run beyond their tolerances.

use std::path::{Path, PathBuf};

use crate::common::{signorini, success_stdout};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-physics-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The committed scene `scene` with `edit` applied to its text, written into `dir`.
fn edited_scene(dir: &Path, scene: &str, edit: impl Fn(String) -> String) -> String {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(scene)).unwrap();
    let path = dir.join("scene.json");
    std::fs::write(&path, edit(text)).unwrap();
    path.to_string_lossy().into_owned()
}

/// The `physics` object of a run's `run.json` in `out`.
fn physics(out: &Path) -> serde_json::Value {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    json["physics"].clone()
}

/// Moreau–Jean with the redistributed mass on the Dirichlet benchmark at NX = 320 over
/// T = 9 (0.4 s): its massless contact node sinks to u(0) = −0.477 (95.6 % of the face's
/// displacement scale D = 0.498) with zero multiplier, then one step snaps it back and the
/// energy rises from 0.1246 to 6.335 (E_max/E_0 = 50.8), while the balance (MJ-E) holds to
/// 1.5e-15. The run is flagged for both, and the balance line says what it does not cover.
/// Crank–Nicolson with the same mass is not flagged.
#[test]
fn moreau_jean_with_a_massless_contact_node_is_flagged_for_penetration_and_energy() {
    let dir = scratch("mj");
    let scene = edited_scene(&dir, "scenes/bar1d-dirichlet.json", |t| {
        t.replace("\"horizon\": 3.0", "\"horizon\": 9.0")
    });
    let run = |scheme: &str, out: &Path| {
        success_stdout(&signorini(&[
            "run",
            &scene,
            "--scheme",
            scheme,
            "--mass",
            "redistributed",
            "--nx",
            "320",
            "--check-balance",
            "--out",
            &out.to_string_lossy(),
        ]))
    };
    let out = dir.join("mj");
    let stdout = run("moreau-jean", &out);
    assert!(stdout.contains("physics FLAGGED: penetrates"), "{stdout}");
    assert!(
        stdout.contains("gains energy: E_max/E_0 = 50.8"),
        "{stdout}"
    );
    assert!(
        stdout.contains("it does not cover whether that change is physical"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(
        (&json["scene"], &json["scheme"], &json["mass"]),
        (
            &serde_json::json!("bar1d-dirichlet"),
            &serde_json::json!("moreau-jean"),
            &serde_json::json!("redistributed")
        ),
        "run.json records what was run"
    );
    let p = physics(&out);
    let penetration = p["penetration"].as_f64().unwrap();
    assert!((penetration - 0.4767).abs() < 1e-3, "{p}");
    assert!(p["relative_penetration"].as_f64().unwrap() > 0.95, "{p}");
    let ratio = p["energy_ratio"].as_f64().unwrap();
    assert!(ratio > 50.0 && ratio < 51.0, "{p}");
    assert_eq!(p["wrong_sign_force"].as_f64(), Some(0.0), "{p}");

    let calm = dir.join("cn");
    let stdout = run("crank-nicolson", &calm);
    assert!(
        stdout.contains("physics: no penetration beyond 1 %"),
        "{stdout}"
    );
    let p = physics(&calm);
    assert!(p["relative_penetration"].as_f64().unwrap() < 1e-12, "{p}");
    assert!(p["energy_ratio"].as_f64().unwrap() < 1.0 + 1e-9, "{p}");
}

/// A synthetic penetration on a 2D box: the bar of `bar2d.json` started 0.25 down, 0.05
/// inside the obstacle 0.2 below it. Its face never leaves the obstacle (D = 0), so the
/// penetration 0.05 is judged against the floor of the displacement scale, and flagged.
#[test]
fn a_box_started_inside_the_obstacle_is_flagged_as_penetrating() {
    let dir = scratch("box");
    let scene = edited_scene(&dir, "scenes/bar2d.json", |t| {
        let t = t
            .replace(
                "\"displacement\": { \"constant\": 0.0 }",
                "\"displacement\": { \"constant\": -0.25 }",
            )
            .replace("\"horizon\": 2.0", "\"horizon\": 0.1");
        let start = t.find("\"fields_at\"").unwrap();
        let end = start + t[start..].find(']').unwrap() + 1;
        format!("{}\"fields_at\": []{}", &t[..start], &t[end..])
    });
    let out = dir.join("out");
    let stdout = success_stdout(&signorini(&[
        "run",
        &scene,
        "--scheme",
        "backward-euler",
        "--mass",
        "standard",
        "--nx",
        "10",
        "--out",
        &out.to_string_lossy(),
    ]));
    assert!(
        stdout.contains("physics FLAGGED: penetrates 5.000e-2 (D = 0)"),
        "{stdout}"
    );
    let p = physics(&out);
    assert!(
        (p["penetration"].as_f64().unwrap() - 0.05).abs() < 1e-12,
        "{p}"
    );
    assert_eq!(p["face_displacement_scale"].as_f64(), Some(0.0), "{p}");
    assert!(p["relative_penetration"].is_null(), "{p}");
}

/// A study's rate tables carry each case's physics: Moreau–Jean with the redistributed mass on
/// the gravity benchmark is marked flagged in its heading, with every flagged level's figures
/// (it sinks 147 % of the face's travel at NX = 160); Crank–Nicolson with the same mass states
/// how far it stayed from the tolerances, and nothing flagged.
#[test]
fn a_study_marks_the_runs_whose_physics_is_flagged() {
    let stdout = success_stdout(&signorini(&[
        "study",
        "scenes/bar1d-gravity.json",
        "--scheme",
        "moreau-jean",
        "--scheme",
        "crank-nicolson",
        "--mass",
        "redistributed",
        "--levels",
        "20,40,80,160",
    ]));
    let heading = |scheme: &str| {
        stdout
            .lines()
            .find(|l| l.starts_with("#### ") && l.contains(scheme))
            .unwrap_or_else(|| panic!("no table of {scheme}: {stdout}"))
            .to_string()
    };
    assert!(
        heading("Moreau–Jean").ends_with("— **physics flagged**"),
        "{stdout}"
    );
    assert!(!heading("Crank–Nicolson").contains("flagged"), "{stdout}");
    assert!(
        stdout.contains("- **NX = 160**: penetrates 7.330e-1 (146.594 % of D = 5.000e-1)"),
        "{stdout}"
    );
    let calm = stdout
        .lines()
        .find(|l| l.starts_with("Physics, every level:"))
        .unwrap_or_else(|| panic!("no physics line for Crank–Nicolson: {stdout}"));
    assert!(calm.ends_with("nothing flagged."), "{calm}");
}
